"""The residual vibration R(τ, ζ) of each built-in rise in numpy closed form: the
peers ``benches/bench_cam_vibration.py`` times cyclomech against (issue 37 row 1)
and ``tests/cam/test_cam_residual_peers.py`` checks it with (not a test module).

Each is derived here by hand from the law's textbook acceleration z''(s) (as a
numpy user would, not from cyclomech's pieces): with λ = −ζτ + iω_d,
ω_d = cτ, c = √(1 − ζ²), the residual amplitude per unit stroke is R = |G|/ω_d,
G = ∫₀¹ e^{λ(1−s)} z''(s) ds (up to its sign). By parts,
∫₀¹ e^{λ(1−s)} p(s) ds = Σ_k [p⁽ᵏ⁾(0)e^{λ} − p⁽ᵏ⁾(1)]/λ^{k+1} for a polynomial,
and a sine piece B·sin(Ωt + φ) on [0, L] gives
B[e^{λL}(λ sin φ + Ω cos φ) − (λ sin ψ + Ω cos ψ)]/(λ² + Ω²), ψ = ΩL + φ.
Since |λ| = τ, 1/λ = κ̄/τ with the constant κ̄ = −ζ − ic: the polynomial laws
are polynomials in t = 1/τ with complex constant coefficients.

Every peer is real arithmetic on float64 arrays, vectorised over τ, in place
where it saves a temporary (``out=``), with the few transcendental calls each
law needs (one ``exp``, one ``cos``/``sin`` pair; the eighths' powers by
products, cheaper in numpy than more transcendental calls). The polynomial laws'
sums cancel at small τ (terms up to 720/τ⁴ and 100800/τ⁶ for a G of O(τ)): they
hold 1e-10 relative for τ ≥ 2 (3-4-5) and τ ≥ 4 (4-5-6-7), as a numpy user's
would; the sine laws lose only ~ε/τ.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import numpy.typing as npt

Array = npt.NDArray[np.float64]

PI2 = math.pi**2
FOUR_PI2 = 4 * PI2
#: Modified sine: peak acceleration Ca = 4π²/(4 + π).
CA_MODSINE = 4 * PI2 / (4 + math.pi)
#: Modified trapezoid: Ca = 8π/(π + 2).
CA_MODTRAP = 8 * math.pi / (math.pi + 2)


def cycloidal(tau: Array, zeta: float) -> Array:
    """z'' = 2π sin 2πs: G = 4π²(e^λ − 1)/(λ² + 4π²), so
    R = 4π²·√[((1 − e)² + 4e·sin²(ω_d/2)) / |λ² + 4π²|²] / ω_d, e = e^{−ζτ}."""
    c = math.sqrt(1 - zeta * zeta)
    wd = tau * c
    e = np.exp(tau * -zeta)
    num = np.sin(wd * 0.5)
    num *= num
    num *= 4 * e
    np.subtract(1.0, e, out=e)
    e *= e
    num += e
    # |λ² + 4π²|² = (τ²(ζ² − c²) + 4π²)² + 4ζ²c²τ⁴.
    t2 = tau * tau
    re = t2 * (zeta * zeta - c * c)
    re += FOUR_PI2
    re *= re
    t2 *= t2
    t2 *= 4 * zeta * zeta * c * c
    re += t2
    num /= re
    np.sqrt(num, out=num)
    num /= wd
    num *= FOUR_PI2
    return num


def harmonic(tau: Array, zeta: float) -> Array:
    """z'' = (π²/2)cos πs: G = (π²/2)·λ(1 + e^λ)/(λ² + π²) (the cosine piece,
    φ = π/2, Ω = π), |λ| = τ and |1 + e^λ|² = (1 − e)² + 4e·cos²(ω_d/2):
    R = (π²/2c)·√[((1 − e)² + 4e·cos²(ω_d/2)) / |λ² + π²|²]."""
    c = math.sqrt(1 - zeta * zeta)
    e = np.exp(tau * -zeta)
    num = np.cos(tau * (0.5 * c))
    num *= num
    num *= 4 * e
    np.subtract(1.0, e, out=e)
    e *= e
    num += e
    t2 = tau * tau
    re = t2 * (zeta * zeta - c * c)
    re += PI2
    re *= re
    t2 *= t2
    t2 *= 4 * zeta * zeta * c * c
    re += t2
    num /= re
    np.sqrt(num, out=num)
    num *= PI2 / (2 * c)
    return num


def _exp_lambda(tau: Array, zeta: float, h: float) -> tuple[Array, Array]:
    """e^{λh} as (real, imaginary) arrays."""
    c = math.sqrt(1 - zeta * zeta)
    w = tau * (c * h)
    m = np.exp(tau * (-zeta * h))
    er = np.cos(w)
    er *= m
    np.sin(w, out=w)
    w *= m
    return er, w


def _cpoly(t: Array, coeffs: list[complex]) -> tuple[Array, Array]:
    """Σ_k coeffs[k]·t^k (complex constants, real t) by Horner, as two real
    arrays."""
    re = np.full_like(t, coeffs[-1].real)
    im = np.full_like(t, coeffs[-1].imag)
    for a in coeffs[-2::-1]:
        re *= t
        re += a.real
        im *= t
        im += a.imag
    return re, im


def polynomial_345(tau: Array, zeta: float) -> Array:
    """z'' = 60s − 180s² + 120s³ (zero at both ends; z''' = 60 at both,
    z'''' = −360 and 360, z⁽⁵⁾ = 720): G = E·P(−t) − P(t) with
    P(t) = 60 + 360κ̄t + 720κ̄²t² up to the unit factor κ̄²t², so
    R = t³/c·|E·P(−t) − P(t)| = t³/c·|(E − 1)·P_even − (E + 1)·P_odd|."""
    c = math.sqrt(1 - zeta * zeta)
    k = complex(-zeta, -c)
    t = 1.0 / tau
    er, ei = _exp_lambda(tau, zeta, 1.0)
    # P_even = 60 + 720κ̄²t², P_odd = 360κ̄t.
    k2 = 720 * k * k
    t2 = t * t
    evr = t2 * k2.real
    evr += 60.0
    evi = t2 * k2.imag
    odr = t * (360 * k.real)
    odi = t * (360 * k.imag)
    # (E − 1)·P_even − (E + 1)·P_odd = E·(P_even − P_odd) − (P_even + P_odd).
    dr = evr - odr
    di = evi - odi
    evr += odr
    evi += odi
    gr = er * dr
    gr -= ei * di
    gr -= evr
    gi = er * di
    ei *= dr
    gi += ei
    gi -= evi
    gr *= gr
    gi *= gi
    gr += gi
    np.sqrt(gr, out=gr)
    t2 *= t
    gr *= t2
    gr *= 1 / c
    return gr


def polynomial_4567(tau: Array, zeta: float) -> Array:
    """z'' = 420s² − 1680s³ + 2100s⁴ − 840s⁵ (z'', z''' zero at both ends;
    z'''' = 840, −840; z⁽⁵⁾ = −10080 at both; z⁽⁶⁾ = 50400, −50400; z⁽⁷⁾ = −100800):
    G = E·Q(−t) + Q(t) with Q(t) = 840 + 10080κ̄t + 50400κ̄²t² + 100800κ̄³t³, up
    to the unit factor κ̄³t³: R = t⁴/c·|(E + 1)·Q_even − (E − 1)·Q_odd|."""
    c = math.sqrt(1 - zeta * zeta)
    k = complex(-zeta, -c)
    t = 1.0 / tau
    er, ei = _exp_lambda(tau, zeta, 1.0)
    t2 = t * t
    evr, evi = _cpoly(t2, [840, 50400 * k * k])
    odr, odi = _cpoly(t2, [10080 * k, 100800 * k**3])
    odr *= t
    odi *= t
    # E·(Q_even − Q_odd) + (Q_even + Q_odd).
    dr = evr - odr
    di = evi - odi
    evr += odr
    evi += odi
    gr = er * dr
    gr -= ei * di
    gr += evr
    gi = er * di
    ei *= dr
    gi += ei
    gi += evi
    gr *= gr
    gi *= gi
    gr += gi
    np.sqrt(gr, out=gr)
    t2 *= t2
    gr *= t2
    gr *= 1 / c
    return gr


def _cmul(ar: Array, ai: Array, br: Array, bi: Array) -> tuple[Array, Array]:
    """(a·b) as two new real arrays."""
    re = ar * br
    re -= ai * bi
    im = ar * bi
    im += ai * br
    return re, im


def _lam2_plus(tau: Array, zeta: float, om2: float) -> tuple[Array, Array]:
    """λ² + Ω² = τ²(ζ² − c²) + Ω² − 2iζcτ²."""
    c2 = 1 - zeta * zeta
    t2 = tau * tau
    re = t2 * (zeta * zeta - c2)
    re += om2
    t2 *= -2 * zeta * math.sqrt(c2)
    return re, t2


def modified_sine(tau: Array, zeta: float) -> Array:
    """Ca·sin 4πs on [0, 1/8], Ca·cos(4π(s − 1/8)/3) on [1/8, 7/8],
    −Ca·cos 4π(s − 7/8) on [7/8, 1]; with q = e^{λ/8}, Ω₁ = 4π, Ω₂ = 4π/3 the
    three sine pieces sum to
    G = Ca·[(q⁷ + q)·λ·(Ω₁² − Ω₂²)/(λ² + Ω₂²) + Ω₁(q⁸ − 1)]/(λ² + Ω₁²)."""
    c = math.sqrt(1 - zeta * zeta)
    o1, o2 = 4 * math.pi, 4 * math.pi / 3
    qr, qi = _exp_lambda(tau, zeta, 0.125)
    q2r, q2i = _cmul(qr, qi, qr, qi)
    q4r, q4i = _cmul(q2r, q2i, q2r, q2i)
    q3r, q3i = _cmul(q2r, q2i, qr, qi)
    q7r, q7i = _cmul(q4r, q4i, q3r, q3i)
    q8r, q8i = _cmul(q4r, q4i, q4r, q4i)
    # s = (q⁷ + q)·λ·(Ω₁² − Ω₂²), λ = −ζτ + icτ.
    q7r += qr
    q7i += qi
    lr = tau * (-zeta * (o1 * o1 - o2 * o2))
    li = tau * (c * (o1 * o1 - o2 * o2))
    sr, si = _cmul(q7r, q7i, lr, li)
    # s/(λ² + Ω₂²) = s·conj(D₂)/|D₂|².
    dr, di = _lam2_plus(tau, zeta, o2 * o2)
    xr = sr * dr
    xr += si * di
    xi = si * dr
    xi -= sr * di
    dr *= dr
    di *= di
    dr += di
    xr /= dr
    xi /= dr
    # + Ω₁(q⁸ − 1).
    q8r -= 1.0
    q8r *= o1
    q8i *= o1
    xr += q8r
    xi += q8i
    xr *= xr
    xi *= xi
    xr += xi
    d1r, d1i = _lam2_plus(tau, zeta, o1 * o1)
    d1r *= d1r
    d1i *= d1i
    d1r += d1i
    xr /= d1r
    np.sqrt(xr, out=xr)
    xr /= tau
    xr *= CA_MODSINE / c
    return xr


def modified_trapezoid(tau: Array, zeta: float) -> Array:
    """Sine ramps of 1/8 (Ω = 4π) joined by plateaus ±Ca of 1/4: with
    q = e^{λ/8} the five pieces sum to
    G = Ca·Ω/(λ² + Ω²)·[(q⁸ − 1) + Ω·q(q² − 1)(q⁴ − 1)/λ], 1/λ = κ̄/τ."""
    c = math.sqrt(1 - zeta * zeta)
    om = 4 * math.pi
    k = complex(-zeta, -c)
    qr, qi = _exp_lambda(tau, zeta, 0.125)
    q2r, q2i = _cmul(qr, qi, qr, qi)
    q4r, q4i = _cmul(q2r, q2i, q2r, q2i)
    q8r, q8i = _cmul(q4r, q4i, q4r, q4i)
    q2r -= 1.0
    q4r -= 1.0
    pr, pi = _cmul(q2r, q2i, q4r, q4i)
    pr, pi = _cmul(pr, pi, qr, qi)
    # ·Ω·κ̄/τ.
    t = om / tau
    xr = pr * k.real
    xr -= pi * k.imag
    xr *= t
    xi = pr * k.imag
    xi += pi * k.real
    xi *= t
    q8r -= 1.0
    xr += q8r
    xi += q8i
    xr *= xr
    xi *= xi
    xr += xi
    dr, di = _lam2_plus(tau, zeta, om * om)
    dr *= dr
    di *= di
    dr += di
    xr /= dr
    np.sqrt(xr, out=xr)
    xr /= tau
    xr *= CA_MODTRAP * om / c
    return xr


#: The peer of each built-in law.
PEERS: dict[str, Callable[[Array, float], Array]] = {
    "cycloidal": cycloidal,
    "harmonic": harmonic,
    "polynomial_345": polynomial_345,
    "polynomial_4567": polynomial_4567,
    "modified_sine": modified_sine,
    "modified_trapezoid": modified_trapezoid,
}

#: Below this τ a law's peer loses more than 1e-10 relative to cancellation
#: (module docs); the sine laws' hold from τ = 0.5 on.
TAU_FROM: dict[str, float] = {"polynomial_345": 2.0, "polynomial_4567": 4.0}
