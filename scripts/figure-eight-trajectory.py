#!/usr/bin/env python3
"""Writes a recorded trajectory CSV of a figure eight (docs/scenarios.md, path.trajectory).

    figure-eight-trajectory.py [--centre X Y] [--half-length A] [--width B]
                               [--rate-hz F] [--wheelbase-m L] > drive.csv

The rear-axle midpoint drives one lap of the lemniscate of Gerono
x = X + A sin u, y = Y + (B/2) sin 2u, from the crossing at (X, Y) back to
it. Its heading is the curve's tangent: a tricycle's rear midpoint cannot
slide. The speed is 0.6 m/s on the crossing and 0.3 m/s where the curve is
tightest (0.6 - 0.3 |k| / max |k|), scaled by a little so that the lap
lasts a whole number of sample intervals and the last sample lands on the
first. Prints the lap's length, time and largest steering angle and
steering rate (for the wheelbase L) on standard error. The defaults made
examples/recorded/figure-eight.csv.
"""
import argparse
import math
import sys


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--centre", nargs=2, type=float, default=[5.0, 4.5], metavar=("X", "Y"))
    parser.add_argument("--half-length", type=float, default=3.5, metavar="A")
    parser.add_argument("--width", type=float, default=3.0, metavar="B")
    parser.add_argument("--rate-hz", type=float, default=20.0, metavar="F")
    parser.add_argument("--wheelbase-m", type=float, default=0.5, metavar="L")
    args = parser.parse_args()
    a, b = args.half_length, args.width
    cx, cy = args.centre

    def velocity(u):  # dr/du
        return a * math.cos(u), b * math.cos(2 * u)

    def curvature(u):
        dx, dy = velocity(u)
        ddx, ddy = -a * math.sin(u), -2 * b * math.sin(2 * u)
        return (dx * ddy - dy * ddx) / math.hypot(dx, dy) ** 3

    steps = 200000  # for the curve's largest curvature and its length
    k_max = max(abs(curvature(2 * math.pi * i / steps)) for i in range(steps))

    def speed(u):
        return 0.6 - 0.3 * abs(curvature(u)) / k_max

    def du_dt(u):  # the parameter's rate at the speed: v / |dr/du|
        return speed(u) / math.hypot(*velocity(u))

    # The lap's time at that speed, Simpson's rule on dt/du.
    lap_s = 0.0
    for i in range(steps + 1):
        weight = 1 if i in (0, steps) else 4 if i % 2 else 2
        lap_s += weight / du_dt(2 * math.pi * i / steps)
    lap_s *= 2 * math.pi / steps / 3
    samples = round(lap_s * args.rate_hz)
    scale = lap_s / (samples / args.rate_hz)  # the speed's factor for whole intervals

    # u(t) by RK4 in 1 ms steps; the last sample is pinned to the lap's end.
    def rate(v):
        return scale * du_dt(v)

    dt = 1 / args.rate_hz
    substeps = max(1, round(dt / 1e-3))
    h = dt / substeps
    u, rows = 0.0, []
    for n in range(samples + 1):
        if n == samples:
            u = 2 * math.pi  # the lap closes exactly
        dx, dy = velocity(u)
        rows.append((n * dt, cx + a * math.sin(u), cy + b / 2 * math.sin(2 * u),
                     math.degrees(math.atan2(dy, dx))))
        for _ in range(substeps):
            k1 = rate(u)
            k2 = rate(u + h / 2 * k1)
            k3 = rate(u + h / 2 * k2)
            k4 = rate(u + h * k3)
            u += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)

    # The length, the steering atan(L k) and its rate v dphi/ds, along the curve.
    length, steer_max, rate_max = 0.0, 0.0, 0.0
    for i in range(steps):
        u0, u1 = 2 * math.pi * i / steps, 2 * math.pi * (i + 1) / steps
        um = (u0 + u1) / 2
        ds = math.hypot(*velocity(um)) * (u1 - u0)
        phi0, phi1 = (math.atan(args.wheelbase_m * curvature(v)) for v in (u0, u1))
        length += ds
        steer_max = max(steer_max, abs(phi1))
        rate_max = max(rate_max, abs(phi1 - phi0) / ds * scale * speed(um))

    # The heading unwrapped, as a recording of a turning robot would be.
    out = ["time_s,x_m,y_m,heading_deg"]
    heading = rows[0][3]
    for i, (t, x, y, deg) in enumerate(rows):
        if i:
            heading += (deg - rows[i - 1][3] + 180) % 360 - 180
        out.append(f"{t:.3f},{x:.6f},{y:.6f},{heading:.6f}")
    sys.stdout.write("\n".join(out) + "\n")
    print(f"one lap: {length:.3f} m in {samples * dt:.3f} s ({samples} intervals), "
          f"steering up to {math.degrees(steer_max):.2f} deg, "
          f"{math.degrees(rate_max):.2f} deg/s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
