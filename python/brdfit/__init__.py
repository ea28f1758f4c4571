"""brdfit: fit parametric BRDF models to measured reflectance, from Python and NumPy.

The same library as the `brdfit` command, with the same results: Model (evaluate any
model and its analytic gradient), read and Samples (data in), fit, compare, select and
export.
Options are keyword arguments named as the command line's ("--max-theta" is max_theta),
declared once, in the library (brdfit.options("fit") lists them).
docs/python.md walks through it."""
from ._compare import CompareResult, compare
from ._data import read
from ._errors import Error, UsageError
from ._export import export
from ._fit import FitResult, fit
from ._model import Model, models, version
from ._options import options
from ._progress import Progress
from ._samples import Samples
from ._select import SelectResult, select

__version__ = version().split(" ")[0]
__all__ = ["__version__", "Error", "UsageError", "Model", "Samples", "FitResult", "CompareResult", "SelectResult",
           "Progress", "models", "options", "read", "fit", "compare", "select", "export", "version"]
