"""The one JSON encoder of cyclomech's output files (results.json, the commands'
summaries): plain Python values from results.

>>> import numpy as np
>>> from cyclomech._json import jsonable
>>> jsonable({("3", "7"): np.float64(30.0), "t": np.array([1.0, np.inf]), "arcs": [("a", "b")]})
{'3→7': 30.0, 't': [1.0, None], 'arcs': ['a→b']}
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["jsonable"]


def jsonable(obj: Any) -> Any:
    """``obj`` with arcs (pairs of event names, as keys or values) written
    ``"x→y"``, numpy arrays and scalars as lists and Python numbers, and
    non-finite floats as None (JSON has no NaN or infinity)."""
    if isinstance(obj, dict):
        return {
            (f"{k[0]}→{k[1]}" if isinstance(k, tuple) else str(k)): jsonable(v)
            for k, v in obj.items()
        }
    if isinstance(obj, tuple) and len(obj) == 2 and all(isinstance(x, str) for x in obj):
        return f"{obj[0]}→{obj[1]}"
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    if isinstance(obj, list | tuple):
        return [jsonable(x) for x in obj]
    if isinstance(obj, np.generic):
        return jsonable(obj.item())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj
