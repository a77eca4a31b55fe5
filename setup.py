"""cffi needs setup.py for ``cffi_modules``; all metadata lives in pyproject.toml."""

from setuptools import setup

setup(cffi_modules=["csrc/cffi_build.py:ffibuilder"])
