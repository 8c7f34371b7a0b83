"""The tour, in Python: enable 8 axes, run S-curve moves with different limits on each, and
print what the card measured against what was asked (examples/tour.rs, step for step).

    python python/examples/tour.py                  # the built-in emulated card
    python python/examples/tour.py --card emu:NAME  # a card-emu process
"""

from __future__ import annotations

import argparse

import motioncard as mc


def e3(x: float) -> str:
    """x as Rust prints `{:.3e}`: 2.000e6, not 2.000e+06."""
    mantissa, exp = f"{x:.3e}".split("e")
    return f"{mantissa}e{int(exp)}"


def plan() -> list[tuple[str, float, mc.MoveLimits]]:
    """One move per axis: (what it shows, distance in counts, limits)."""
    return [
        ("long, cruises", 400_000.0, mc.MoveLimits(200_000.0, 2e6, 1e8)),
        (
            "long, asymmetric acc/dec",
            -300_000.0,
            mc.MoveLimits(150_000.0, 3e6, 1e8, deceleration=1e6, decel_jerk=2e7),
        ),
        ("short, no cruise", 20_000.0, mc.MoveLimits(400_000.0, 2e6, 1e8)),
        ("tiny, acc limit never hit", 500.0, mc.MoveLimits(100_000.0, 4e6, 5e7)),
        ("soft jerk", 100_000.0, mc.MoveLimits(120_000.0, 1.5e6, 1e7)),
        ("stiff jerk", -150_000.0, mc.MoveLimits(250_000.0, 2.5e6, 5e8)),
        ("slow and long", 50_000.0, mc.MoveLimits(25_000.0, 2e5, 2e6)),
        ("quick decel", 250_000.0, mc.MoveLimits(300_000.0, 1e6, 5e7, deceleration=4e6)),
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--card", default="sim", help="sim, emu:NAME, uio:/dev/uioN or pci:DDDD:BB:DD.F")
    args = ap.parse_args()
    with mc.Card.open(args.card) as card:
        info = card.info
        v = info.firmware_version
        print(
            f"card {args.card}: firmware {v >> 16}.{(v >> 8) & 0xFF}.{v & 0xFF}, "
            f"layout {info.layout[0]}.{info.layout[1]}, {info.axes} axes, "
            f"servo {info.servo_rate_hz} Hz"
        )
        moves = plan()[: info.axes]
        axes = card.axes()
        motions = []
        for axis, (_, dist, lim) in zip(axes, moves):
            axis.enable()
            start = axis.status().command_position
            motions.append((start + dist, axis.move_relative(dist, lim)))
        print()
        print(
            f"{'axis':<4} {'move':<26} {'target':>10} {'final':>10} {'plan s':>8} {'exec s':>8}  "
            f"{'peak v / limit':>19}  {'peak a / limit':>19}  {'peak d / limit':>19}  "
            f"{'peak |j| / max j':>19}  {'|ferr|':>7}"
        )
        worst_miss = 0.0
        for axis, (what, _, lim), (target, motion) in zip(axes, moves, motions):
            reached = motion.wait(30.0)
            s = axis.status()
            jmax = max(lim.jerks)
            worst_miss = max(worst_miss, abs(reached - target))
            print(
                f"{axis.index:<4} {what:<26} {target:>10.0f} {reached:>10.0f} "
                f"{s.planned_time:>8.4f} {s.move_time:>8.4f}  "
                f"{s.peak_velocity:>9.0f}/{lim.velocity:<9.0f}  "
                f"{e3(s.peak_acceleration):>9}/{e3(lim.acceleration):<9}  "
                f"{e3(s.peak_deceleration):>9}/{e3(lim.deceleration):<9}  "
                f"{e3(s.peak_jerk):>9}/{e3(jmax):<9}  {s.max_following_error:>7.2f}"
            )
        print()
        print(
            "positions and following errors in encoder counts; "
            "exec = start to in-position (motion done)"
        )
        print("peak |j| is the largest jerk of the move, against the largest of its four phase jerks")
        print(f"worst |final - target| = {worst_miss:g} counts")
        for axis in axes:
            axis.disable()


if __name__ == "__main__":
    main()
