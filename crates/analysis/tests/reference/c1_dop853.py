"""Independent reference for case C1: stroboscopic points by SciPy's DOP853 (Hairer's 8th-order
Dormand-Prince with its own error control), written from the equations alone, with no code shared
with geardyn. Regenerate with `python3 c1_dop853.py` (numpy, scipy); the test
`lanes_strobe_points_match_an_independent_dop853_solution` (crates/analysis/tests/lanes.rs)
embeds its output.

Case C1 (dimensionless): x'' + F_m = F + xi*omega^2*cos(omega*tau), with
F_m = k(tau)*(x - D) + c*x' for x >= D, 0 for |x| < D, k(tau)*(x + D) + c*x' for x <= -D,
k(tau) = 1 + 0.2*cos(omega*tau), D = 1, c = 0.1, F = 0.1, xi = 0.2 (damping only in contact).
The contact region is tracked as a mode; the switching surfaces x = +-D are located by SciPy's
event finder and the integration restarts there in the new region.
"""

import numpy as np
from scipy.integrate import solve_ivp

D, C, F, XI, KAPPA = 1.0, 0.1, 0.1, 0.2, 0.2
RTOL, ATOL = 1e-12, 1e-13


def field(omega, region):
    def f(t, y):
        x, v = y
        k = 1.0 + KAPPA * np.cos(omega * t)
        if region > 0:
            fm = k * (x - D) + C * v
        elif region < 0:
            fm = k * (x + D) + C * v
        else:
            fm = 0.0
        return [v, F + XI * omega**2 * np.cos(omega * t) - fm]

    return f


def events(region):
    """Guards leaving `region` (direction of the crossing that leaves it)."""
    if region > 0:
        g = [lambda t, y: y[0] - D]
        d = [-1]
    elif region < 0:
        g = [lambda t, y: y[0] + D]
        d = [1]
    else:
        g = [lambda t, y: y[0] - D, lambda t, y: y[0] + D]
        d = [1, -1]
    for e, s in zip(g, d):
        e.terminal = True
        e.direction = s
    return g


def region_of(x):
    return 1 if x >= D else (-1 if x <= -D else 0)


def strobe(omega, y0, first, count):
    """States at tau = j*2*pi/omega, j = first .. first + count - 1, from y0 at tau = 0."""
    T = 2 * np.pi / omega
    t, y = 0.0, np.array(y0, float)
    region = region_of(y[0])
    out = []
    for j in range(1, first + count):
        t_end = j * T
        while True:
            sol = solve_ivp(
                field(omega, region),
                (t, t_end),
                y,
                method="DOP853",
                rtol=RTOL,
                atol=ATOL,
                max_step=T / 64,
                events=events(region),
            )
            if sol.status == 1:  # a surface: restart in the region entered
                for gi, (te, ye) in enumerate(zip(sol.t_events, sol.y_events)):
                    if len(te):
                        t, y = te[0], ye[0].copy()
                        break
                if region == 0:
                    region = 1 if gi == 0 else -1
                else:
                    region = 0
                continue
            t, y = t_end, sol.y[:, -1].copy()
            break
        if j >= first:
            out.append((j, y[0], y[1]))
    return out


if __name__ == "__main__":
    # (omega, start, first period, periods): period-1 orbits and the period-2 orbit at 0.95 from
    # rest (drive contact and separation), and at 1.8 the coexisting period-3 orbit with
    # back-side contact from a start inside its basin
    cases = [(w, (0.0, 0.0), 300, 4) for w in (0.6, 0.8, 0.95, 1.8, 2.0)]
    cases.append((1.8, (0.7, -1.48), 600, 6))
    for omega, y0, first, count in cases:
        for j, x, v in strobe(omega, y0, first, count):
            print(f"({omega}, {y0[0]}, {y0[1]}, {j}, {float(x)!r}, {float(v)!r}),")
