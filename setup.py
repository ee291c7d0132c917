"""The native part of the package: ``exudyn_wheelrail.native.direct_force`` (C++, pybind11), through which Exudyn
calls the compiled contact evaluation without Python (``exudyn_wheelrail/multibody/direct_call.py``).  Everything
else is declared in ``pyproject.toml``.  The extension is optional: without a C++ compiler the install still
succeeds and the connector takes its Python path (``WheelRailContact.call_path`` says which runs)."""
from pybind11.setup_helpers import Pybind11Extension
from setuptools import setup

setup(ext_modules=[Pybind11Extension("exudyn_wheelrail.native.direct_force",
                                     ["exudyn_wheelrail/native/direct_force.cpp"],
                                     cxx_std=17, optional=True)])
