"""The harness's modules sit beside its test, not in a package: put them on the path."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
