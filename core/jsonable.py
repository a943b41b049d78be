"""The one JSON cleaner: results as plain JSON values, never NaN or infinity."""

from __future__ import annotations

import json
import math
from dataclasses import fields, is_dataclass
from pathlib import PurePath

import numpy as np


def to_jsonable(value):
    """A JSON-able copy of ``value``: dataclasses and mappings as dicts, arrays and tuples as
    lists, numpy scalars as Python numbers, paths as text; NaN and infinities as None (JSON
    has no such numbers, and most readers refuse Python's ``NaN``/``Infinity``)."""
    if is_dataclass(value) and not isinstance(value, type):
        return {f.name: to_jsonable(getattr(value, f.name)) for f in fields(value)}
    if isinstance(value, dict):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, np.ndarray):
        return [to_jsonable(v) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [to_jsonable(v) for v in value]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, PurePath):
        return str(value)
    return value


def dumps(value, **kwargs) -> str:
    """``json.dumps`` of `to_jsonable(value)`; raises rather than writing NaN."""
    return json.dumps(to_jsonable(value), allow_nan=False, **kwargs)
