#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Why stiffness damping shrinks BIE's stable step, on a linear model small enough to solve exactly.

A chain of `nb` point masses (a brick's dofs, total mass m) joined by brick springs kb (implicit
midpoint, Rayleigh damping C = beta K, as eq. 4.6) and held at both ends by mortar springs ki
(explicit Verlet). One BIE step with `iters` iterations of the constant J of eq. 4.7 (the mortar
term neglected) is a linear map of (p, v, a); the step is stable while its spectral radius is
<= 1. The script bisects the largest stable h (in units of 1 / omega_i, omega_i = sqrt(ki / m);
nan: unstable even at 1e-3 / omega_i) for 1-4 iterations and several beta omega_b (omega_b: the chain's highest brick frequency),
writing CSV to stdout:  devenv/nacre-env run python3 perf/bie/iteration_stability.py
The residual forms are those of docs/methods.md ("The BIE step"): G_p, G_v, x += J^-1 G.
"""
import numpy as np


def spectral_radius(M, K, C, Ki, h, iters):
    n = M.shape[0]
    Mi = np.linalg.inv(M)
    I = np.eye(n)
    J = np.block([[I + h * h / 4 * Mi @ K, h * h / 4 * Mi @ C], [h / 2 * Mi @ K, I + h / 2 * Mi @ C]])
    Ji = np.linalg.inv(J)
    acc = lambda P, V: Mi @ (-Ki @ P - K @ P - C @ V)
    A = np.zeros((3 * n, 3 * n))
    for c in range(3 * n):
        s = np.zeros(3 * n)
        s[c] = 1
        p, v, a = s[:n], s[n:2 * n], s[2 * n:]
        x = np.concatenate([p, v])
        for _ in range(iters):
            P, V = x[:n], x[n:]
            dp, dv = P - p, V - v
            Gp = h * v + h * h / 2 * a - h * h / 4 * Mi @ (K @ dp + C @ dv) - dp
            Gv = h / 2 * (a + acc(P, V)) - dv
            x = x + Ji @ np.concatenate([Gp, Gv])
        P, V = x[:n], x[n:]
        A[:, c] = np.concatenate([P, V, acc(P, V)])
    return max(abs(np.linalg.eigvals(A)))


def critical(M, K, C, Ki, iters, wi):
    """Largest stable h (bisection in log h), or nan where even h = 1e-3 / omega_i is unstable."""
    lo, hi = 1e-3 / wi, 1e2 / wi
    if spectral_radius(M, K, C, Ki, lo, iters) > 1 + 1e-9:
        return float("nan")
    for _ in range(60):
        mid = np.sqrt(lo * hi)
        if spectral_radius(M, K, C, Ki, mid, iters) <= 1 + 1e-9:
            lo = mid
        else:
            hi = mid
    return lo


def main():
    m, ki, ratio, nb = 1.0, 1.0, 500.0, 3
    kb = ratio * ki
    M = np.eye(nb) * m / nb
    K = np.zeros((nb, nb))
    for j in range(nb - 1):
        K[j, j] += kb
        K[j + 1, j + 1] += kb
        K[j, j + 1] -= kb
        K[j + 1, j] -= kb
    Ki = np.zeros((nb, nb))
    Ki[0, 0] = Ki[-1, -1] = ki
    wi = np.sqrt(ki / m)
    wb = np.sqrt(max(np.linalg.eigvals(np.linalg.inv(M) @ K).real))
    print("beta_omega_b,iterations,h_crit_omega_i")
    for bw in [0.0, 1.0, 10.0, 30.0, 100.0, 300.0, 1000.0]:
        C = (bw / wb) * K
        for it in [1, 2, 3, 4]:
            print(f"{bw:g},{it},{critical(M, K, C, Ki, it, wi) * wi:.4f}")


if __name__ == "__main__":
    main()
