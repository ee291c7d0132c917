"""Native code of the package: ``direct_force`` (built from ``direct_force.cpp`` at install, when a C++ compiler is
there), the functions through which Exudyn calls the compiled contact call without Python
(:mod:`exudyn_wheelrail.multibody.direct_call`)."""
