"""lamodel: limit analysis of dry masonry block assemblies with Coulomb friction.

The minimum collapse multiplier of a frictional (non-associative) assembly from the
mathematical program of eq. (5) of the seed paper: statically admissible states,
kinematically admissible mechanisms of a fictitious system with cohesion -mu N, and the
bilinear condition alpha = -u^T f0 - xi^T N_mu s_N.

Layers (docs/architecture.md): :mod:`lamodel.io` (files in), :mod:`lamodel.structure`
(the data), :mod:`lamodel.geometry` (contacts from polygons, generators),
:mod:`lamodel.formulation` (eq. 1-5: matrices and the Pyomo model), :mod:`lamodel.search`
(LPs, certification, GA, Ipopt, the driver), :mod:`lamodel.output` (results, modes,
pictures, comparison, and :func:`lamodel.analyse`: what ``lamodel solve`` does, from Python),
:mod:`lamodel.cli`.

The names below load on first use: ``import lamodel`` does not import Pyomo, so reading
results or comparing them starts quickly. ``SolverFactory('lamodel_ipopt')`` (Debian's
libipopt through cyipopt) is registered by :mod:`lamodel.solvers.bridge`, which the Pyomo
model imports, and at ``import lamodel`` when Pyomo is already loaded.
"""
import logging
import sys
from importlib import import_module

from .errors import InputError, SolverError  # noqa: F401

# The search logs to "lamodel" (phases and lanes at INFO, each step at DEBUG); the library
# adds no handler but this one, so an application's own logging set-up decides what shows.
logging.getLogger("lamodel").addHandler(logging.NullHandler())

__version__ = "0.3.0"

_LAZY = {
    "Structure": "lamodel.structure",
    "read": "lamodel.io",
    "read_dat": "lamodel.io.datfile",
    "write_dat": "lamodel.io.datfile",
    "structure_from_json": "lamodel.io.jsonspec",
    "structure_to_json": "lamodel.io.jsonspec",
    "solve": "lamodel.search.driver",
    "SolveOptions": "lamodel.search.options",
    "Results": "lamodel.output.results",
    "analyse": "lamodel.output.present",
    "Analysis": "lamodel.output.present",
    "LimitAnalysisBlock": "lamodel.formulation.model",
    "create_model": "lamodel.formulation.model",
    "create_abstract_model": "lamodel.formulation.model",
    "solve3d": "lamodel.search.search3d",
    "extrude": "lamodel.formulation.extrude",
    "LimitAnalysisBlock3D": "lamodel.formulation.model3d",
    "create_model3d": "lamodel.formulation.model3d",
}

__all__ = ["InputError", "SolverError", *_LAZY]


def __getattr__(name):
    if name in _LAZY:
        value = getattr(import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'lamodel' has no attribute '{name}'")


def __dir__():
    return sorted(list(globals()) + list(_LAZY))


if "pyomo.environ" in sys.modules:  # a Pyomo user: SolverFactory('lamodel_ipopt') at no extra cost
    import_module("lamodel.solvers.bridge")
