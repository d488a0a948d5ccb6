"""Edge validation: errors that name the field, the value and the allowed range."""
from __future__ import annotations

import math


class InputError(ValueError):
    """Invalid user input. The message names the field, the value and the allowed range."""


def require_finite(field: str, value: float) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{field} = {value!r} is not a number") from None
    if not math.isfinite(v):
        raise InputError(f"{field} = {value!r} must be finite")
    return v


def require_range(field: str, value: float, lo: float | None = None, hi: float | None = None,
                  lo_open: bool = False, hi_open: bool = False, unit: str = "") -> float:
    """Check lo <= value <= hi (strict where *_open); return value as float."""
    v = require_finite(field, value)
    bad = ((lo is not None and (v < lo or (lo_open and v == lo)))
           or (hi is not None and (v > hi or (hi_open and v == hi))))
    if bad:
        left = "-inf" if lo is None else f"{lo:g}"
        right = "inf" if hi is None else f"{hi:g}"
        lb = "(" if (lo is None or lo_open) else "["
        rb = ")" if (hi is None or hi_open) else "]"
        u = f" {unit}" if unit else ""
        raise InputError(f"{field} = {v:g}{u} is outside the allowed range {lb}{left}, {right}{rb}{u}")
    return v


def require_positive(field: str, value: float, unit: str = "") -> float:
    return require_range(field, value, lo=0.0, lo_open=True, unit=unit)


def require_table(where: str, value, allowed) -> dict:
    """The one check of a TOML table (a scene's, a study's, an unknowns file's): `value` must be a
    table whose keys are all in `allowed`; the first unknown key is named with the allowed ones."""
    if not isinstance(value, dict):
        raise InputError(f"{where} = {value!r} must be a table with keys {', '.join(allowed)}")
    unknown = [k for k in value if k not in allowed]
    if unknown:
        raise InputError(f"{where}: unknown key '{unknown[0]}' (allowed: {', '.join(allowed)})")
    return value
