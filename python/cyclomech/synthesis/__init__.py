"""Synthesis: mechanisms dimensioned from what they must do (issue 35).

Where the other domains analyse a mechanism whose dimensions the designer
brings, this one starts a step earlier, from what the mechanism must do: an
input–output relation (function generation), points a coupler point must pass
(path generation), poses a coupler must take (motion generation), a cam's
limits at given phase angles and speed (cam sizing). Every function returns
the dimensions with the margins of the constraints it was asked to hold.
"""

from __future__ import annotations

from ._cam_size import *  # noqa: F403
from ._cam_size import __all__ as _cam_size_all

__all__ = [*_cam_size_all]  # filled as the kinds of synthesis land
