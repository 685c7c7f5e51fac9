"""Shared by the tests that compare with scipy (sobol_scipy_test.py, sobol_mse_scipy_test.py).

A missing scipy is a failure, not a skip: CI always has it, and a silent skip would hide a
regression.
"""
import sys


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def import_scipy():
    """numpy, scipy and scipy.stats.qmc, or a failure that says how to get them."""
    try:
        import numpy
        import scipy
        from scipy.stats import qmc
    except ImportError as error:
        fail(f"cannot import scipy ({error}) with {sys.executable}: install python3-scipy "
             "(scripts/setup.sh) or point CMake's Python3_EXECUTABLE at an interpreter that has it")
    return numpy, scipy, qmc
