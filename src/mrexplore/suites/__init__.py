"""The benchmark suites that ship with mrexplore (``mrexplore suite list``).

Each ``<name>.toml`` here is a released suite; a released suite never changes, a new
version is a new file. The format is read by :mod:`mrexplore.experiments.suite`.
"""
