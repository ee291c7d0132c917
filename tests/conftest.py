"""Test-suite configuration: Hypothesis profiles.

Every property-based test (``@given``) draws its examples under a profile chosen by the environment variable
``WHEELRAIL_HYPOTHESIS_PROFILE``:

* ``repro`` (the default): derandomized -- the examples are a fixed function of the test, so a run gives the same
  result on every machine, every time (for a given Hypothesis version), and no example database is read or
  written.  This is what CI and a developer's ``python -m pytest`` run.
* ``wide``: a fresh random seed per run, the local example database (``.hypothesis/``) on, so a failure found once is
  replayed first on the next run.  The per-test example counts stay those written in each ``@settings``; repeat
  the run to search wider.  A failure prints the seed and a ``@reproduce_failure`` blob to replay it.  E.g.::

      WHEELRAIL_HYPOTHESIS_PROFILE=wide python -m pytest -q tests/test_creep_laws.py tests/test_hertz.py
      for i in 1 2 3 4 5; do WHEELRAIL_HYPOTHESIS_PROFILE=wide python -m pytest -q -x tests -k "random or fuzz"; done
      python -m pytest -q tests/test_hertz.py --hypothesis-seed=12345 --hypothesis-profile=wide   # replay a seed

  (``--hypothesis-profile NAME`` on the command line selects a profile too, and wins over the variable.)

The long validations (the paper's full runs, the long fuzz runs of ``tests/stress``, fine-grid sweeps) are marked
``validation`` and left out of the default run: ``python -m pytest -m validation`` runs them all.
Tests set only what is specific to them (example count, health checks, ``deadline=None`` for compiled code whose
first call compiles); randomness and the database are the profile's.

In a parallel run (pytest-xdist, one worker per CPU) a first compilation stays in its worker's process
(``jit.COMPILE_AHEAD_ENV=0``): the workers already use every CPU, and a second compiling process per worker would
only compete with them.
"""
import os

from hypothesis import settings

from exudyn_wheelrail.jit import COMPILE_AHEAD_ENV

if int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")) > 1:
    os.environ.setdefault(COMPILE_AHEAD_ENV, "0")

settings.register_profile("repro", derandomize=True, database=None, deadline=None, print_blob=True)
settings.register_profile("wide", derandomize=False, deadline=None, print_blob=True)
settings.load_profile(os.environ.get("WHEELRAIL_HYPOTHESIS_PROFILE", "repro"))
