"""Numerics of compare_bags.py: interpolation of a sampled trace, the lag
between two traces, the spindle angle made monotone, distances of points to
a polyline, and the RMS."""
import math

import numpy as np

MIN_SAMPLES = 10            # fewer spindle/tension samples (in the overlap) cannot be aligned
RAD_S_PER_RPM = 2.0 * math.pi / 60.0   # the one rpm conversion of the Python tools


def hermite(xq, x, y):
    """Cubic Hermite interpolation of y(x) at xq (x strictly increasing), slopes
    by central differences: third order, so a ripple sampled at 6 points per
    period is interpolated far better than linearly (matters for the lag)."""
    x, y, xq = np.asarray(x, float), np.asarray(y, float), np.asarray(xq, float)
    if len(x) < 3:
        return np.interp(xq, x, y)
    m = np.empty_like(y)
    m[1:-1] = (y[2:] - y[:-2]) / (x[2:] - x[:-2])
    m[0] = (y[1] - y[0]) / (x[1] - x[0])
    m[-1] = (y[-1] - y[-2]) / (x[-1] - x[-2])
    i = np.clip(np.searchsorted(x, xq, side="right") - 1, 0, len(x) - 2)
    h = x[i + 1] - x[i]
    u = (xq - x[i]) / h
    u2, u3 = u * u, u * u * u
    return ((2 * u3 - 3 * u2 + 1) * y[i] + (u3 - 2 * u2 + u) * h * m[i]
            + (-2 * u3 + 3 * u2) * y[i + 1] + (u3 - u2) * h * m[i + 1])


def estimate_lag(tm, ym, ts, ys, max_lag):
    """Lag tau [s] with machine(t) ~ sim(t - tau) + const.

    Coarse: on a uniform grid (the machine's median step h), the integer shift
    minimizing the variance of machine - shifted sim (equivalent to the peak of
    the cross-correlation, insensitive to an offset). Fine: golden-section
    search of the same variance over tau in [k-1, k+1] h, with the sim trace
    interpolated (cubic Hermite) at the machine's own stamps.
    Returns (lag_s, residual_rms) or (None, reason)."""
    lo, hi = max(tm[0], ts[0]), min(tm[-1], ts[-1])
    h = float(np.median(np.diff(tm)))
    if hi - lo < 4 * h:
        return None, "overlap too short"
    max_lag = min(max_lag, 0.25 * (hi - lo))
    K = max(1, int(max_lag / h))
    grid = np.arange(lo, hi, h)
    gm = np.interp(grid, tm, ym)
    gs = np.interp(grid, ts, ys)
    if np.std(gm) == 0 or np.std(gs) == 0:
        return None, "a trace is constant"
    n = len(grid)
    if n <= 2 * K + MIN_SAMPLES:
        return None, "overlap too short for the lag search"
    costs = np.array([np.var(gm[K:n - K] - gs[K - k:n - K - k]) for k in range(-K, K + 1)])
    kbest = int(np.argmin(costs)) - K
    # Machine samples whose shifted times stay inside the sim's record for every tau tried.
    sel = (tm >= ts[0] + (abs(kbest) + 2) * h) & (tm <= ts[-1] - (abs(kbest) + 2) * h)
    if sel.sum() < MIN_SAMPLES:
        return None, "overlap too short"
    tsel, ysel = tm[sel], ym[sel]

    def cost(tau):
        return float(np.var(ysel - hermite(tsel - tau, ts, ys)))

    a, b = (kbest - 1) * h, (kbest + 1) * h
    g = (math.sqrt(5) - 1) / 2
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = cost(c), cost(d)
    while b - a > 1e-7:   # 0.1 us
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = cost(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = cost(d)
    tau = 0.5 * (a + b)
    # Identifiable only where the shifted sim trace explains the machine's
    # variation: a flat trace under noise has a least-squares minimum at a
    # lag that means nothing.
    explained = 1.0 - cost(tau) / float(np.var(ysel))
    if explained < 0.5:
        return None, ("not identifiable: the shifted simulation explains %.0f %% of the "
                      "machine trace's variance (less than 50 %%; a flat trace under noise)"
                      % (100.0 * max(explained, 0.0)))
    return tau, math.sqrt(cost(tau))


def monotone_angle(theta):
    """Spindle angle made increasing (either turning direction) and a mask of
    the samples that advance it: standstill or backlash samples are dropped,
    because they do not map to a unique angle."""
    sign = 1.0 if theta[-1] >= theta[0] else -1.0
    u = sign * theta
    runmax = np.maximum.accumulate(u)
    keep = np.ones(len(u), bool)
    keep[1:] = u[1:] > runmax[:-1]
    return u, keep


def point_to_polyline(points, poly, chunk=2000):
    """Distance [m] of each point (N x 3) to the polyline through poly (M x 3)."""
    a, b = poly[:-1], poly[1:]
    ab = b - a
    ab2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-30)
    out = np.empty(len(points))
    step = max(1, chunk * 200 // max(len(a), 1))
    for s in range(0, len(points), step):
        p = points[s:s + step, None, :]                               # n x 1 x 3
        u = np.clip(np.einsum("nmk,mk->nm", p - a[None], ab) / ab2, 0.0, 1.0)
        q = a[None] + u[..., None] * ab[None]                          # n x m x 3
        out[s:s + step] = np.sqrt(np.min(np.sum((p - q) ** 2, axis=2), axis=1))
    return out


def rms(x):
    return float(np.sqrt(np.mean(np.square(x)))) if len(x) else None
