"""Numbers printed for people: the one rule of the command line, the warnings and the
error messages.

A value cyclomech computed (a stroke taken from a cam, a limit, a speed) is printed
with 6 significant digits (``%.6g``, which is what ``{x:g}`` gives too); a value the
user wrote is echoed as written (``repr``) so that it can be found in the file.
When 6 digits would print a computed value equal to the value it is compared with,
both are printed in full (``repr``): "0.0094 must be smaller than 0.0094" would not
say what is wrong. Files for programs (CSV, JSON, parquet) keep full precision; this
rule is for text only.

>>> from cyclomech._numtext import number_text
>>> number_text(0.009399999999599031)
'0.0094'
>>> number_text(0.009399999999599031, 0.0094)     # would read equal to 0.0094
'0.009399999999599031'
"""

from __future__ import annotations

__all__ = ["SIGNIFICANT", "number_text"]

#: The significant digits of a computed number printed for people.
SIGNIFICANT = 6


def number_text(value: float, *compared: float) -> str:
    """``value`` with :data:`SIGNIFICANT` significant digits, or in full (``repr``) when
    that would print it equal to one of ``compared`` although it differs.

    Parameters
    ----------
    value : float
        The number, in whatever unit the text names.
    *compared : float
        The numbers the text compares it with (in the same unit).

    Returns
    -------
    str
        The text of ``value``.

    Examples
    --------
    >>> number_text(2.0 / 3.0), number_text(1234567.0), number_text(1.0 + 1e-12, 1.0)
    ('0.666667', '1.23457e+06', '1.000000000001')
    """
    v = float(value)
    short = f"{v:.{SIGNIFICANT}g}"
    for c in compared:
        c = float(c)
        if c != v and f"{c:.{SIGNIFICANT}g}" == short:
            return repr(v)
    return short
