"""The machine moving: every mechanism at its own phase over one cycle.

:func:`machine_scenes` asks each mechanism's result for its :class:`Scene` at the
main shaft's angles (a kind that can be drawn has ``scene(cycle_deg)``; the
machine has no per-kind code), :func:`animation_section` puts them in the
report — a canvas per mechanism and the cyclogram with a cursor, drawn by a small
script with play/pause and a slider, the data inline (no server, no network) —
and :mod:`cyclomech.machine.plot` draws a frame or writes a GIF from the same
scenes.

Frame k of F is at the main shaft's angle k·cycle/F [deg].

>>> import cyclomech as cm
>>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"), progress=False)
>>> frame_angles(r, 4).tolist(), [op["title"] for op in timeline(r)["ops"]][:2]
([0.0, 90.0, 180.0, 270.0], ['clamp the pile', 'cut'])
"""

from __future__ import annotations

import html
import json
from typing import TYPE_CHECKING, Any

import numpy as np

from .._arrays import count
from .._scene import Array, Scene

if TYPE_CHECKING:
    from ._result import MachineResult

__all__ = ["FRAMES", "animation_section", "frame_angles", "machine_scenes", "timeline"]

#: Frames per cycle in the report's animation (3° apart on a 360° cycle).
FRAMES = 120


def machine_scenes(result: MachineResult, frames: int = FRAMES) -> tuple[Array, dict[str, Scene]]:
    """(the main shaft's angles [deg], each drawable mechanism's scene there by name).

    Frame k is at k·cycle/``frames`` (:func:`scenes_at` those angles).
    """
    theta = frame_angles(result, frames)
    return theta, scenes_at(result, theta)


def frame_angles(result: MachineResult, frames: int) -> Array:
    """The main shaft's angles [deg] of ``frames`` frames over the cycle: k·cycle/frames."""
    n = count("frames", frames, low=2, what="frames over the cycle")
    return np.arange(n, dtype=np.float64) * (float(result.machine.cyclogram.cycle_deg) / n)


def scenes_at(result: MachineResult, cycle_deg: Array) -> dict[str, Scene]:
    """Each drawable mechanism's scene at the main shaft's angles ``cycle_deg``
    [deg], by name: a mechanism whose result has no ``scene`` hook, or whose scene
    needs the optimum the machine lacks, is left out."""
    out: dict[str, Scene] = {}
    for name, res in result.mechanisms.items():
        get = getattr(res, "scene", None)
        s = None if get is None else get(cycle_deg)
        if s is not None:
            out[name] = s
    return out


def timeline(result: MachineResult) -> dict[str, Any]:
    """The optimum's operations for the cursor's chart: rows (mechanisms, in order of
    first appearance; ``(other)`` for an operation without one) and each operation's
    row, start and angle [deg], title and whether it is critical (no operations
    without an optimum)."""
    o = result.optimum
    rows: list[str] = []
    ops: list[dict[str, Any]] = []
    if o is not None:
        critical = set(o.critical)
        for op in result.machine.cyclogram.operations:
            row = op.mechanism or "(other)"
            if row not in rows:
                rows.append(row)
            ops.append(
                {
                    "row": rows.index(row),
                    "start": float(o.times[op.src]),
                    "angle": float(o.angles[op.arc]),
                    "title": op.title,
                    "critical": op.arc in critical,
                }
            )
    return {"rows": rows, "ops": ops, "cycle": float(result.machine.cyclogram.cycle_deg)}


def _flat(a: Array, scale: float = 1e3) -> list[float | None]:
    """``a`` flattened, times ``scale`` (m → mm), to 4 decimals; NaN → None (null)."""
    v = np.round(np.asarray(a, dtype=np.float64).ravel() * scale, 4)
    return [None if not np.isfinite(x) else float(x) for x in v]


def _scene_json(s: Scene) -> dict[str, Any]:
    """A scene for the page's script: lengths in mm, each point's frames as
    [x0, y0, x1, y1, …], each body's outline likewise and its poses as
    [x, y, angle (rad)] per frame."""
    bodies = []
    for b in s.bodies.values():
        pose = np.asarray(b.pose, dtype=np.float64).copy()
        pose[:, :2] *= 1e3
        bodies.append(
            {
                "outline": _flat(b.outline),
                "pose": [float(x) for x in np.round(pose.ravel(), 6)],
                "closed": b.closed,
                "fill": b.fill,
            }
        )
    return {
        "name": s.name,
        "box": [round(1e3 * v, 4) for v in s.box()],
        "points": {p: _flat(v) for p, v in s.points.items()},
        "links": [list(ln) for ln in s.links],
        "ground": list(s.ground),
        "bodies": bodies,
        "traces": list(s.traces),
    }


def animation_data(result: MachineResult, frames: int = FRAMES) -> dict[str, Any] | None:
    """What the page's script draws (JSON-ready): the angles [deg], the scenes
    (lengths in mm) and the timeline; None when no mechanism can be drawn."""
    theta, scenes = machine_scenes(result, frames)
    if not scenes:
        return None
    return {
        "theta": [float(t) for t in np.round(theta, 9)],
        "scenes": [_scene_json(s) for s in scenes.values()],
        "timeline": timeline(result),
    }


def animation_section(result: MachineResult, frames: int = FRAMES) -> list[str]:
    """The report's section "The machine moving": the controls, a canvas per
    mechanism, the cyclogram with its cursor, the data and the script (none when
    nothing can be drawn; a note when the machine has no optimum to time it)."""
    if result.optimum is None:
        return [
            "<h2>The machine moving</h2>",
            "<p class='note'>Not drawn: the cyclogram does not fit at the nominal speed, so "
            "the mechanisms have no timing to move by.</p>",
        ]
    data = animation_data(result, frames)
    if data is None:
        return []
    e = html.escape
    n = len(data["theta"])
    canvases = "".join(
        f"<figure class='cm-fig'><canvas class='cm-scene' width='420' height='340' "
        f"data-k='{k}'></canvas><figcaption>{e(s['name'])}</figcaption></figure>"
        for k, s in enumerate(data["scenes"])
    )
    rows = max(len(data["timeline"]["rows"]), 1)
    payload = json.dumps(data, allow_nan=False, separators=(",", ":")).replace("</", "<\\/")
    return [
        "<h2>The machine moving</h2>",
        "<p>Every mechanism at its own phase over one cycle of the optimised timing, "
        f"{n} frames, {data['timeline']['cycle'] / n:g}° apart; the cursor on the "
        "cyclogram below is the main shaft's angle. Each point is where the "
        "mechanism's solver puts it at that angle (lengths to scale within each "
        "drawing; the thin line is the output point's path).</p>",
        "<div id='cm-anim'><div class='cm-ctrl'>"
        "<button id='cm-play' type='button'>Play</button> "
        f"<input id='cm-slider' type='range' min='0' max='{n - 1}' step='1' value='0' "
        "aria-label='main-shaft angle'> <span id='cm-angle'>θ = 0°</span></div>"
        f"<div class='cm-scenes'>{canvases}</div>"
        f"<canvas id='cm-timeline' width='1000' height='{34 + 22 * rows}'></canvas></div>",
        f"<script type='application/json' id='cm-anim-data'>{payload}</script>",
        f"<script>{_SCRIPT}</script>",
    ]


#: The page's player: draws the scenes and the timeline at a frame; play/pause,
#: the slider. No library, no network.
_SCRIPT = """
(function () {
  "use strict";
  var D = JSON.parse(document.getElementById("cm-anim-data").textContent);
  var F = D.theta.length, frame = 0, timer = null;
  var slider = document.getElementById("cm-slider");
  var play = document.getElementById("cm-play");
  var label = document.getElementById("cm-angle");
  var canvases = Array.prototype.slice.call(document.querySelectorAll("canvas.cm-scene"));
  var tl = document.getElementById("cm-timeline");
  function fit(c, box) {
    var pad = 8, w = c.width - 2 * pad, h = c.height - 2 * pad;
    var s = Math.min(w / (box[1] - box[0]), h / (box[3] - box[2]));
    var ox = pad + (w - s * (box[1] - box[0])) / 2 - s * box[0];
    var oy = c.height - pad - (h - s * (box[3] - box[2])) / 2 + s * box[2];
    return function (x, y) { return [ox + s * x, oy - s * y]; };
  }
  function at(S, p, i) {
    var a = S.points[p], x = a[2 * i], y = a[2 * i + 1];
    return (x === null || y === null) ? null : [x, y];
  }
  function path(g, T, xy, close) {
    g.beginPath();
    var pen = false;
    for (var k = 0; k < xy.length; k++) {
      if (!xy[k]) { pen = false; continue; }
      var q = T(xy[k][0], xy[k][1]);
      if (pen) { g.lineTo(q[0], q[1]); } else { g.moveTo(q[0], q[1]); pen = true; }
    }
    if (close) { g.closePath(); }
  }
  function drawScene(c, S, i) {
    var g = c.getContext("2d"), T = fit(c, S.box), k, p;
    g.clearRect(0, 0, c.width, c.height);
    g.lineJoin = "round"; g.lineCap = "round";
    S.traces.forEach(function (p) {
      var xy = [];
      for (k = 0; k < F; k++) { xy.push(at(S, p, k)); }
      path(g, T, xy, false); g.strokeStyle = "#6aa5d8"; g.lineWidth = 1; g.stroke();
    });
    S.bodies.forEach(function (b) {
      var x = b.pose[3 * i], y = b.pose[3 * i + 1], a = b.pose[3 * i + 2];
      var co = Math.cos(a), si = Math.sin(a), xy = [];
      for (k = 0; k < b.outline.length; k += 2) {
        var u = b.outline[k], v = b.outline[k + 1];
        xy.push(u === null ? null : [x + co * u - si * v, y + si * u + co * v]);
      }
      path(g, T, xy, b.closed);
      if (b.fill) { g.fillStyle = "#dfe5ec"; g.fill(); }
      g.strokeStyle = "#4a4a4a"; g.lineWidth = 1.2; g.stroke();
    });
    S.links.forEach(function (ln) {
      var xy = ln.map(function (p) { return at(S, p, i); });
      if (xy.some(function (q) { return !q; })) { return; }
      path(g, T, xy, xy.length > 2);
      if (xy.length > 2) { g.fillStyle = "rgba(31,119,180,0.18)"; g.fill(); }
      g.strokeStyle = "#1b3a5c"; g.lineWidth = 3; g.stroke();
    });
    S.ground.forEach(function (p) {
      var q = at(S, p, i);
      if (!q) { return; }
      q = T(q[0], q[1]);
      g.beginPath(); g.moveTo(q[0], q[1]); g.lineTo(q[0] - 7, q[1] + 12);
      g.lineTo(q[0] + 7, q[1] + 12); g.closePath();
      g.fillStyle = "#fff"; g.fill(); g.strokeStyle = "#333"; g.lineWidth = 1; g.stroke();
    });
    for (p in S.points) {
      var q = at(S, p, i);
      if (!q) { continue; }
      q = T(q[0], q[1]);
      g.beginPath(); g.arc(q[0], q[1], 3.2, 0, 2 * Math.PI);
      g.fillStyle = "#fff"; g.fill(); g.strokeStyle = "#1b3a5c"; g.lineWidth = 1.3; g.stroke();
    }
  }
  function drawTimeline(i) {
    var g = tl.getContext("2d"), t = D.timeline, left = 150, right = 24, top = 8;
    var w = tl.width - left - right, rowH = 22;
    function X(deg) { return left + w * deg / t.cycle; }
    g.clearRect(0, 0, tl.width, tl.height);
    g.font = "12px system-ui, sans-serif"; g.textBaseline = "middle";
    t.rows.forEach(function (r, k) {
      g.fillStyle = "#222"; g.textAlign = "right";
      g.fillText(r, left - 8, top + rowH * k + rowH / 2);
    });
    t.ops.forEach(function (op) {
      var y = top + rowH * op.row + 3, s = op.start % t.cycle, e = s + op.angle;
      var parts = e > t.cycle ? [[s, t.cycle], [0, e - t.cycle]] : [[s, e]];
      parts.forEach(function (pr) {
        g.fillStyle = "#9ec5e8"; g.fillRect(X(pr[0]), y, X(pr[1]) - X(pr[0]), rowH - 6);
        g.strokeStyle = op.critical ? "#c0392b" : "#4a6d8c"; g.lineWidth = 1;
        g.strokeRect(X(pr[0]), y, X(pr[1]) - X(pr[0]), rowH - 6);
      });
    });
    var bottom = top + rowH * Math.max(t.rows.length, 1);
    g.strokeStyle = "#888"; g.beginPath(); g.moveTo(left, bottom); g.lineTo(left + w, bottom);
    g.stroke(); g.fillStyle = "#444"; g.textAlign = "center";
    for (var d = 0; d <= t.cycle + 1e-9; d += t.cycle / 6) {
      g.fillText(Math.round(d) + "°", X(d), bottom + 12);
    }
    var x = X(D.theta[i]);
    g.strokeStyle = "#d62728"; g.lineWidth = 2;
    g.beginPath(); g.moveTo(x, top - 4); g.lineTo(x, bottom + 2); g.stroke();
  }
  function show(i) {
    frame = i; slider.value = String(i);
    label.textContent = "θ = " + D.theta[i].toFixed(1) + "°";
    canvases.forEach(function (c) { drawScene(c, D.scenes[+c.dataset.k], i); });
    drawTimeline(i);
  }
  function pause() {
    if (timer !== null) { clearInterval(timer); timer = null; }
    play.textContent = "Play";
  }
  play.addEventListener("click", function () {
    if (timer !== null) { pause(); return; }
    timer = setInterval(function () { show((frame + 1) % F); }, 1000 / 24);
    play.textContent = "Pause";
  });
  slider.addEventListener("input", function () { pause(); show(+slider.value); });
  show(0);
})();
"""
