"""Ready linkages of seed 001: the knife drives of single-knife cutting machines.

Each function returns a :class:`~cyclomech.Linkage` that solves over the full
crank turn, with the knife holder's free joint ``E`` as its output.

* :func:`burg_trimmer` — the seed's data (l1 = 0.425 m … H2 = 1.184 m, crank
  l6 = 0.102 m, ψ = 150°). Structure 1–3: the crank OF and one class III group,
  the knife holder B–C–E held by the hangers AB and DC and the rod EF. Frame after
  the seed's loop equations (its eq. for BR-125 with the origin at A): D = (−H11,
  0), the crank centre O = (H12, H2), BC = l3, BE = l4 at ψ from the direction
  C→B. Every length is the seed's; the drawn pose only picks the assembly.
* :func:`br125`, :func:`br136`, :func:`brp4` — the seed's generalized scheme with
  p = 1, 2, 3 (structures 1–3, 1–2–3 and 1–2–2–3). **Illustrative dimensions**:
  the seed gives their schemes, not their sizes.

>>> from cyclomech.linkage import presets
>>> sorted(presets.NAMES)
['br125', 'br136', 'brp4', 'burg_trimmer']
"""

from __future__ import annotations

import math
from collections.abc import Callable

from .._errors import InputError
from ._linkage import Linkage

__all__ = ["NAMES", "br125", "br136", "brp4", "burg_trimmer", "get"]

_KNIFE_LINKS = [("A", "B"), ("D", "C"), ("B", "C", "E"), ("E", "F")]


def _knife(
    name: str,
    points: dict[str, tuple[float, float]],
    l1: float,
    l2: float,
    l3: float,
    l4: float,
    l5: float,
    psi_deg: float,
    drive: list[tuple[str, ...]],
    ground: list[str],
    driver: tuple[str, str],
) -> Linkage:
    """The knife-holder group with the seed's lengths; ``points`` a pose near it.

    ψ turns the direction C→B into B→E, so the triangle's angle at B is 180° − ψ.
    """
    ce = math.sqrt(l3 * l3 + l4 * l4 + 2 * l3 * l4 * math.cos(math.radians(psi_deg)))
    lengths = {
        ("A", "B"): l1,
        ("D", "C"): l2,
        ("B", "C"): l3,
        ("B", "E"): l4,
        ("C", "E"): ce,
        ("E", "F"): l5,
    }
    return Linkage(
        points, _KNIFE_LINKS + drive, ground, driver, lengths=lengths, name=name, output="E"
    )


def burg_trimmer() -> Linkage:
    """The Burg trimmer's knife drive from the seed's data (seed 001).

    The crank angle is absolute about O; drawn at φ6 = 0 on the near-parallelogram
    assembly of the hangers (the one whose hanger angle φ1 runs through
    123°–154°).

    Returns
    -------
    Linkage
        The linkage (lengths in metres), named ``"Burg trimmer"``, output ``E``.

    Examples
    --------

    >>> import numpy as np
    >>> from cyclomech.linkage import presets
    >>> lk = presets.burg_trimmer()
    >>> lk.structure
    [('driver', ('F',)), ('III', ('B', 'C', 'E'))]
    >>> bool(lk.solve(np.linspace(0, 2 * np.pi, 361)).ok.all())
    True
    """
    h11, h12, h2, l6 = 1.51, -0.184, 1.184, 0.102
    points = {
        "A": (0.0, 0.0),
        "D": (-h11, 0.0),
        "O": (h12, h2),
        "B": (-0.294171255633039, 0.306738116899874),
        "C": (-1.80378552558479, 0.340866638081327),
        "E": (-0.447981857274456, 0.400238377983497),
        "F": (h12 + l6, h2),
    }
    return _knife(
        "Burg trimmer",
        points,
        0.425,
        0.450,
        1.510,
        0.180,
        0.865,
        150.0,
        [("O", "F")],
        ["A", "D", "O"],
        ("O", "F"),
    )


def br125() -> Linkage:
    """BR-125 knife drive, structure 1–3 (crank + class III group).

    Illustrative dimensions (the Burg design scaled to a 1.25 m knife).

    Returns
    -------
    Linkage
        The linkage (lengths in metres), named ``"BR-125"``, output ``E``.

    Examples
    --------

    >>> from cyclomech.linkage import presets
    >>> presets.br125().structure[-1]
    ('III', ('B', 'C', 'E'))
    """
    points = {
        "A": (0.0, 0.0),
        "D": (-1.25, 0.0),
        "O": (-0.15, 0.98),
        "B": (-0.253555722050306, 0.255557226107085),
        "C": (-1.50324755357266, 0.283311977525593),
        "E": (-0.381762221725227, 0.333423094374924),
        "F": (-0.065, 0.98),
    }
    return _knife(
        "BR-125",
        points,
        0.36,
        0.38,
        1.25,
        0.15,
        0.72,
        150.0,
        [("O", "F")],
        ["A", "D", "O"],
        ("O", "F"),
    )


def br136() -> Linkage:
    """BR-136 knife drive, structure 1–2–3.

    Crank OJ, a dyad (rod JF, rocker GF) driving the class III group; illustrative
    dimensions.

    Returns
    -------
    Linkage
        The linkage (lengths in metres), named ``"BR-136"``, output ``E``.

    Examples
    --------

    >>> from cyclomech.linkage import presets
    >>> [kind for kind, _ in presets.br136().structure]
    ['driver', 'II', 'III']
    """
    points = {
        "A": (0.0, 0.0),
        "D": (-1.36, 0.0),
        "G": (-0.16, 1.07),
        "O": (0.06, 1.69),
        "B": (-0.208613151142068, 0.32951563418232),
        "C": (-1.56840898387294, 0.353080296024925),
        "E": (-0.345770257516639, 0.411904517964993),
        "F": (0.059849272855501, 1.07814231078426),
        "J": (0.16, 1.69),
    }
    drive: list[tuple[str, ...]] = [("G", "F"), ("J", "F"), ("O", "J")]
    return _knife(
        "BR-136",
        points,
        0.39,
        0.41,
        1.36,
        0.16,
        0.78,
        150.0,
        drive,
        ["A", "D", "G", "O"],
        ("O", "J"),
    )


def brp4() -> Linkage:
    """BRP-4 knife drive, the seed's generalized scheme with every parameter non-zero.

    Crank OJ, ternary coupler J–K–M with rocker PK, rod MF and rocker GF, then the
    class III group (1–2–2–3); illustrative dimensions.

    Returns
    -------
    Linkage
        The linkage (lengths in metres), named ``"BRP-4"``, output ``E``.

    Examples
    --------

    >>> from cyclomech.linkage import presets
    >>> [kind for kind, _ in presets.brp4().structure]
    ['driver', 'II', 'point', 'II', 'III']
    """
    points = {
        "A": (0.0, 0.0),
        "D": (-1.36, 0.0),
        "G": (-0.16, 1.07),
        "O": (0.3, 1.75),
        "P": (0.55, 1.45),
        "B": (-0.177566883852205, 0.34723191350885),
        "C": (-1.53738222704037, 0.369642456341529),
        "E": (-0.314793867409907, 0.429504357155883),
        "F": (0.0991841556223891, 1.09058090071667),
        "J": (0.39, 1.75),
        "K": (0.691803007219655, 1.64362827051715),
        "M": (0.270006250132939, 1.74877525805121),
    }
    drive = [("G", "F"), ("M", "F"), ("J", "K", "M"), ("P", "K"), ("O", "J")]
    return _knife(
        "BRP-4",
        points,
        0.39,
        0.41,
        1.36,
        0.16,
        0.78,
        150.0,
        drive,
        ["A", "D", "G", "O", "P"],
        ("O", "J"),
    )


#: Each preset's name and the function that builds its :class:`~cyclomech.Linkage`.
NAMES: dict[str, Callable[[], Linkage]] = {
    "burg_trimmer": burg_trimmer,
    "br125": br125,
    "br136": br136,
    "brp4": brp4,
}


def get(name: str) -> Linkage:
    """A preset by name (one of :data:`NAMES`).

    Parameters
    ----------
    name : str
        The preset's name: ``"burg_trimmer"``, ``"br125"``, ``"br136"`` or
        ``"brp4"``.

    Returns
    -------
    Linkage
        A new linkage of that preset.

    Raises
    ------
    InputError
        If there is no preset of that name.

    Examples
    --------

    >>> from cyclomech.linkage import presets
    >>> presets.get("burg_trimmer").name
    'Burg trimmer'
    """
    try:
        return NAMES[name]()
    except (KeyError, TypeError):
        raise InputError(
            f"no preset {name!r}; the presets are {', '.join(sorted(NAMES))}"
        ) from None
