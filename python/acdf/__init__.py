# The package acdf: everything the compiled extension acdf._acdf defines (docs/python.md), with its
# docstring and the project's version.
from ._acdf import *  # noqa: F403
from ._acdf import __doc__, __version__  # noqa: F401
