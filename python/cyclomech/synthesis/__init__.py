"""Synthesis: mechanisms dimensioned from what they must do (issue 35).

Where the other domains analyse a mechanism whose dimensions the designer
brings, this one starts a step earlier, from what the mechanism must do: an
input–output relation (function generation), points a coupler point must pass
(path generation), poses a coupler must take (motion generation), a cam's
limits at given phase angles and speed (cam sizing). Every function returns
the dimensions with the margins of the constraints it was asked to hold.
"""

from __future__ import annotations

from ._fourbar import (
    Margins,
    four_bar_linkage,
    four_bar_margins,
    slider_crank_linkage,
    slider_crank_margins,
)
from ._path import PathCandidate, path_evaluate, path_generation

__all__ = []  # type: list[str]  # filled as the kinds of synthesis land
__all__ += ["Margins", "four_bar_linkage", "four_bar_margins", "slider_crank_linkage"]
__all__ += ["slider_crank_margins"]
__all__ += ["PathCandidate", "path_evaluate", "path_generation"]
