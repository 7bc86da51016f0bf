"""The package list (the rest of the configuration is pyproject.toml's).

The targets' templates live in the top-level templates/<target>/ (the layout the project asks for)
and ship in the wheel as the package `adbgen.templates` (pyproject's package-dir maps it there);
setuptools' automatic discovery finds packages by their folders only, so the mapped one is added here.
"""

from setuptools import find_packages, setup

setup(packages=find_packages(include=["adbgen*", "generated*"]) + ["adbgen.templates"])
