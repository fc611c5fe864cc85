"""A module imported on first use, for annotations.

limbfuse does not import pandas with the package (``to_pandas`` and
``from_pandas`` import it when called), so ``pd`` was defined for type
checkers only and ``typing.get_type_hints`` on anything annotated
``pd.DataFrame`` raised ``NameError: name 'pd' is not defined``. Each module
that annotates with pandas now binds ``pd = LazyModule("pandas")`` at run
time: evaluating ``pd.DataFrame`` imports pandas then (and raises
``ModuleNotFoundError`` if it is not installed), importing limbfuse does not.
"""

from __future__ import annotations

import importlib
from typing import Any


class LazyModule:
    """Stands for the module `name`; an attribute lookup imports it."""

    def __init__(self, name: str) -> None:
        self._lazy_name = name

    def __getattr__(self, attr: str) -> Any:
        # (only attributes not set in __init__ come here)
        return getattr(importlib.import_module(self._lazy_name), attr)

    def __repr__(self) -> str:
        return f"<module {self._lazy_name!r}, imported on first use>"
