"""Validation of numeric parameters: scalars broadcast over a size, vectors checked."""

from __future__ import annotations

import numbers

import numpy as np

from .exceptions import InvalidParameter


def vector_parameter(owner: str, name: str, value, size: int, *, minimum: float | None = None,
                     strict: bool = False, allow_inf: bool = False) -> np.ndarray:
    """``value`` (scalar or sequence) as a float vector of ``size``.

    Args:
        owner: Named in the error, e.g. ``"task 'arms'"``.
        name: Parameter name.
        value: A scalar (broadcast) or a sequence of ``size`` numbers.
        size: Expected length.
        minimum: Lower bound of every element, if any.
        strict: Whether the bound is strict (``> minimum``).
        allow_inf: Whether infinite elements are accepted (never NaN).

    Raises:
        InvalidParameter: wrong type, shape or range.
    """
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError) as error:
        raise InvalidParameter(owner, name, value, f"a number or {size} numbers") from error
    if array.ndim == 0:
        array = np.full(size, float(array))
    if array.shape != (size,):
        raise InvalidParameter(owner, name, value, f"a number or {size} numbers")
    if np.isnan(array).any() or (not allow_inf and np.isinf(array).any()):
        raise InvalidParameter(owner, name, value,
                               "finite numbers" if not allow_inf else "numbers (no NaN)")
    if minimum is not None:
        bad = array <= minimum if strict else array < minimum
        if bad.any():
            relation = ">" if strict else ">="
            raise InvalidParameter(owner, name, value, f"every element {relation} {minimum}")
    return array


def scalar_parameter(owner: str, name: str, value, *, minimum: float | None = None,
                     strict: bool = False) -> float:
    """``value`` as a finite float, optionally bounded below."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not np.isfinite(value):
        raise InvalidParameter(owner, name, value, "a finite number")
    if minimum is not None and (value <= minimum if strict else value < minimum):
        raise InvalidParameter(owner, name, value,
                               f"a number {'>' if strict else '>='} {minimum}")
    return float(value)


def integer_parameter(owner: str, name: str, value, *, minimum: int = 0) -> int:
    """``value`` as an int not below ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < minimum:
        raise InvalidParameter(owner, name, value, f"an integer >= {minimum}")
    return int(value)
