"""Packaging of what pyproject.toml cannot list statically (the rest of the configuration is there).

* The targets' templates live in the top-level templates/<target>/ (the layout the project asks for)
  and ship in the wheel as the package `adbgen.templates`.
* Each model folder of the checkout's generated/ goes into the wheel as the package
  adbgen.models.<model> (with its C, CVODE and AUTO-07p files, pyproject.toml's package data), so an
  installed adbgen has no top-level `generated` package to collide with another project's.  In the
  checkout itself generated/ stays where it is; adbgen/models/__init__.py points there.

setuptools' automatic discovery finds packages by their folders only, so the mapped ones are listed here.
"""

from pathlib import Path

from setuptools import find_packages, setup

ROOT = Path(__file__).resolve().parent
MODELS = sorted(p.parent.name for p in (ROOT / "generated").glob("*/__init__.py"))

setup(packages=find_packages(include=["adbgen", "adbgen.*"]) + ["adbgen.templates"]
      + [f"adbgen.models.{m}" for m in MODELS],
      package_dir={"adbgen.templates": "templates", **{f"adbgen.models.{m}": f"generated/{m}" for m in MODELS}})
