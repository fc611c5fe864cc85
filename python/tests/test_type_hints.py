"""`typing.get_type_hints` on the public API (session 28): it raised
``NameError: name 'pd' is not defined`` for every annotation naming pandas
(imported for type checkers only, so that importing limbfuse does not import
pandas) and ``name 'Estimate' is not defined`` for ``report`` (an import
hidden from run time to break an import cycle). Now every callable in
``limbfuse.__all__`` (and in ``limbfuse.cohort.__all__``), and every public
method and property of its classes, has hints that resolve, to the real
classes; importing limbfuse still does not import pandas."""

import inspect
import subprocess
import sys
import typing

import pytest

import limbfuse

pd = pytest.importorskip("pandas")


def _members(cls):
    """The public methods and property getters a class defines or inherits
    from limbfuse classes (``__init__`` included)."""
    for klass in cls.__mro__:
        if not klass.__module__.startswith("limbfuse"):
            continue
        for name, attr in vars(klass).items():
            if name.startswith("_") and name != "__init__":
                continue
            if isinstance(attr, property):
                yield f"{cls.__name__}.{name}", attr.fget
            elif isinstance(attr, (staticmethod, classmethod)):
                yield f"{cls.__name__}.{name}", attr.__func__
            elif inspect.isfunction(attr):
                yield f"{cls.__name__}.{name}", attr


def _public():
    """(name, object) of every public callable, classes and their members."""
    cohort = limbfuse.cohort
    named = [(n, getattr(limbfuse, n)) for n in limbfuse.__all__]
    named += [(f"cohort.{n}", getattr(cohort, n)) for n in cohort.__all__]
    for name, obj in named:
        if inspect.isclass(obj):
            yield name, obj
            yield from _members(obj)
        elif callable(obj):
            yield name, obj


PUBLIC = list(_public())


@pytest.mark.parametrize("name,obj", PUBLIC, ids=[n for n, _ in PUBLIC])
def test_type_hints_resolve(name, obj):
    typing.get_type_hints(obj)


def test_the_walk_covers_the_api_and_pandas_hints_are_pandas():
    names = {n for n, _ in PUBLIC}
    for n in ["estimate", "report", "Trial.to_pandas", "Trial.from_pandas", "Estimate.to_pandas", "Filter.run", "cohort.run"]:
        assert n in names, n
    assert typing.get_type_hints(limbfuse.Estimate.to_pandas)["return"] is pd.DataFrame
    assert typing.get_type_hints(limbfuse.cohort.run)["return"] is pd.DataFrame
    report = typing.get_type_hints(limbfuse.report)["estimates"]
    assert limbfuse.Estimate in typing.get_args(report)


def test_importing_limbfuse_does_not_import_pandas():
    code = "import sys, limbfuse; print('pandas' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False", out.stderr
