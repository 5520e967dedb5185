"""lamodel: limit analysis of dry masonry block assemblies with Coulomb friction.

The minimum collapse multiplier of a frictional (non-associative) assembly from the
mathematical program of eq. (5) of the seed paper: statically admissible states,
kinematically admissible mechanisms of a fictitious system with cohesion -mu N, and the
bilinear condition alpha = -u^T f0 - xi^T N_mu s_N.
"""
from .errors import InputError, SolverError
from .structure import Structure
from . import bridge  # noqa: F401  registers SolverFactory('lamodel_ipopt')
from .model import LimitAnalysisBlock, create_abstract_model, create_model  # noqa: F401
from .datfile import read_dat, write_dat

__all__ = ["InputError", "SolverError", "Structure", "LimitAnalysisBlock", "create_abstract_model",
           "create_model", "read_dat", "write_dat"]
__version__ = "0.1.0"
