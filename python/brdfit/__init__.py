"""brdfit: fit parametric BRDF models to measured reflectance, from Python and NumPy.

The same library as the `brdfit` command, with the same results: Model (evaluate any
model and its analytic gradient), read and Samples (data in), fit, compare, select,
tradeoff and export; info, render, fit_images and read_all (the commands info, render,
fit-images, and many files at once).
Options are keyword arguments named as the command line's ("--max-theta" is max_theta),
declared once, in the library (brdfit.options("fit") lists them).
docs/python.md walks through it."""
from ._compare import CompareResult, compare
from ._data import read
from ._errors import Error, UsageError
from ._export import export
from ._fit import FitResult, fit
from ._folders import read_all
from ._info import Info, LoadReport, info
from ._model import Model, models, version
from ._options import options
from ._photo import FitImagesResult, fit_images
from ._progress import Progress
from ._render import render
from ._samples import Samples
from ._select import SelectResult, select
from ._tradeoff import TradeoffResult, tradeoff

__version__ = version().split(" ")[0]
__all__ = ["__version__", "Error", "UsageError", "Model", "Samples", "FitResult", "CompareResult", "SelectResult",
           "TradeoffResult", "Progress", "models", "options", "read", "fit", "compare", "select", "tradeoff", "export",
           "version", "Info", "LoadReport", "FitImagesResult", "info", "render", "fit_images", "read_all"]
