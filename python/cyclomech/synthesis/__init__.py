"""Synthesis: mechanisms dimensioned from what they must do (issue 35).

Where the other domains analyse a mechanism whose dimensions the designer
brings, this one starts a step earlier, from what the mechanism must do: an
input–output relation (function generation), points a coupler point must pass
(path generation), poses a coupler must take (motion generation), a cam's
limits at given phase angles and speed (cam sizing). Every function returns
the dimensions with the margins of the constraints it was asked to hold.
"""

from __future__ import annotations

from ._knife import KnifeDrive, KnifeRequirement, knife_drive, knife_motion
from ._knife_compare import KnifeComparison, compare_knife_drives, knife_forces
from ._knife_file import SYNTHESIZE_KEYS, KnifeSynthesis  # registers the linkage synthesizer

__all__ = [  # filled as the kinds of synthesis land
    "SYNTHESIZE_KEYS",
    "KnifeComparison",
    "KnifeDrive",
    "KnifeRequirement",
    "KnifeSynthesis",
    "compare_knife_drives",
    "knife_drive",
    "knife_forces",
    "knife_motion",
]
