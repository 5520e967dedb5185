"""Numerical solvers lamodel plugs into the libraries it uses, knowing nothing of masonry:
:mod:`.bridge` registers Ipopt (through cyipopt) as the Pyomo solver ``'lamodel_ipopt'``."""
