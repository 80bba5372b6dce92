"""Cams sized against the cyclogram (issue 35, item 7): `_cam_size` part of
:mod:`cyclomech.synthesis`, its door. The sizing lives in the cam domain
(``cyclomech/cam/_size.py``, beside the criteria it evaluates and the machine
kind that asks for it); this module only names it here.
"""

from __future__ import annotations

from ..cam import (
    CAM_SIZE_CRITERIA,
    CamLimits,
    CamSize,
    CamSizeTradeoff,
    cam_size,
    cam_size_tradeoff,
)

__all__ = [
    "CAM_SIZE_CRITERIA",
    "CamLimits",
    "CamSize",
    "CamSizeTradeoff",
    "cam_size",
    "cam_size_tradeoff",
]
