"""Cams sized against the cyclogram (issue 35, item 7): `_cam_size` part of
:mod:`cyclomech.synthesis`, its door. The sizing lives in the cam domain
(``cyclomech/cam/_size.py``, beside the criteria it evaluates and the machine
kind that asks for it); this module only names it here.

>>> import cyclomech as cm
>>> S = cm.cam.Segment
>>> cam = cm.cam.Cam([S("rise", 90, 0.02), S("dwell", 90), S("return", 150, 0.02),
...                   S("dwell", 30)], cm.cam.TranslatingRoller(0.05, 0.01))
>>> r = cam_size(cam, 300.0, max_base_radius=0.2)
>>> round(r.base_radius * 1e3, 3), r.binding
(25.019, 'pressure_angle')
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
