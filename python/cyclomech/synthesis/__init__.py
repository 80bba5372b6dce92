"""Synthesis: mechanisms dimensioned from what they must do (issue 35).

Where the other domains analyse a mechanism whose dimensions the designer
brings, this one starts a step earlier, from what the mechanism must do: an
input–output relation (function generation), points a coupler point must pass
(path generation), poses a coupler must take (motion generation), a cam's
limits at given phase angles and speed (cam sizing). Every function returns
the dimensions with the margins of the constraints it was asked to hold.

Four-bars and slider-cranks, function and motion generation
-----------------------------------------------------------
Every four-bar or slider-crank result reports a :class:`Margins` (Grashof type,
whether the crank turns fully, the transmission angle's extremes over the
working range in closed form, branch, link-length ratio; also
:func:`four_bar_margins`, :func:`slider_crank_margins`) and builds its
:class:`cyclomech.Linkage` (:func:`four_bar_linkage`,
:func:`slider_crank_linkage`), so that the position solver analyses it like any
drawn linkage. :func:`function_generation` solves Freudenstein's equation (in
Norton's convention, angles from the ground line A → D) exactly through three
precision points — Chebyshev-spaced by :func:`chebyshev_points` or given —
or by least squares through more, reports the structural error over the whole
input range, and does the same for a slider-crank's position.
:func:`motion_generation` takes three poses of the coupler and builds four-bars
from two circle points (given, or scanned on a grid and ranked), their centre
points the circumcentres of their three positions. Candidates come best first:
clean ones (no branch or order defect, no fold over the range) before the
others, each with its defects and margins.

>>> import cyclomech as cm
>>> best = cm.synthesis.function_generation([(30, 80), (60, 90), (90, 100)], ground_m=0.2)[0]
>>> best.margins.grashof, best.clean
('crank-rocker', True)
"""

from __future__ import annotations

from ._dwell import DwellCandidate, dwell_sixbar
from ._fourbar import (
    Margins,
    four_bar_linkage,
    four_bar_margins,
    slider_crank_linkage,
    slider_crank_margins,
)
from ._function import FunctionCandidate, chebyshev_points, function_generation
from ._motion import MotionCandidate, motion_generation

__all__ = []  # type: list[str]  # filled as the kinds of synthesis land
__all__ += ["Margins", "four_bar_linkage", "four_bar_margins", "slider_crank_linkage"]
__all__ += ["slider_crank_margins"]
__all__ += ["FunctionCandidate", "chebyshev_points", "function_generation"]
__all__ += ["MotionCandidate", "motion_generation"]
__all__ += ["DwellCandidate", "dwell_sixbar"]
