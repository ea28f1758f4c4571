"""Results as NumPy and pandas users take them: the library's JSON numbers as floats (its
null, written for NaN and for what does not apply, as NaN), and records as a DataFrame."""
from __future__ import annotations

import importlib
import math
from typing import Any, Dict, List, Mapping, Sequence

# One NaN object for every missing number: dicts holding it compare equal (Python's ==
# on containers takes an object as equal to itself), so two results' .metrics compare as
# their values do.
NAN = math.nan


def _number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def floats(v: Any) -> Any:
    """A JSON value with every number a float and every null NaN, through dicts and lists
    (booleans and strings as they are)."""
    if v is None:
        return NAN
    if _number(v):
        return float(v)
    if isinstance(v, Mapping):
        return {k: floats(x) for k, x in v.items()}
    if isinstance(v, list):
        return [floats(x) for x in v]
    return v


def params_floats(v: Any) -> Any:
    """A "params" or "stderr" object as floats (NaN for null); None where the record has
    none (a fit that did not run)."""
    return None if v is None else floats(v)


def _column(values: Sequence[Any]) -> Any:
    """A column's values typed: numbers and nulls only (a column of nulls too) become
    floats with NaN; any other column keeps its values (None for null)."""
    if all(v is None or _number(v) for v in values):
        return [NAN if v is None else float(v) for v in values]
    return list(values)


def _pandas() -> Any:
    try:
        return importlib.import_module("pandas")
    except ImportError as e:
        raise ImportError("brdfit: to_dataframe() needs pandas (Debian: apt install python3-pandas; "
                          "pip: pip install pandas): %s" % e) from None


def frame(records: List[Dict[str, Any]], nested: Sequence[str] = ()) -> Any:
    """A pandas DataFrame of records (dicts with the same keys, in order), one row each:
    number columns as float64 (NaN for null); the keys in nested ("params", "stderr")
    as a column of dicts of floats; everything else (strings, booleans, lists) as it is."""
    pd = _pandas()
    keys: List[str] = []
    for r in records:
        keys.extend(k for k in r if k not in keys)
    cols: Dict[str, Any] = {}
    for k in keys:
        values = [r.get(k) for r in records]
        if k in nested:
            cols[k] = pd.Series([params_floats(v) for v in values], dtype=object)
        else:
            typed = _column(values)
            cols[k] = pd.Series(typed, dtype="float64" if typed and all(isinstance(v, float) for v in typed)
                                else None)
    return pd.DataFrame(cols, columns=keys)
