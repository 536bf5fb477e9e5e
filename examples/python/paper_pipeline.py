"""The paper's pipeline from Python, notebook style: simulate -> identify -> diagnose -> add the
missing effect -> stationary FPK and a power sweep, with figures.

    python examples/python/paper_pipeline.py [--quick] [--out out/python_pipeline]

--quick (CI) shrinks the ensembles; without it the sizes are the paper's (100 records x 10^5
samples) and the README's missing-physics example (100 records x 500 time units).
"""
import argparse
import os
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import vehs  # noqa: E402
import vehs.plot  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


_clock = [time.perf_counter()]


def section(title):
    now = time.perf_counter()
    print(f"  ({now - _clock[0]:.1f} s)\n\n== {title}")
    _clock[0] = now


def table(model, truth):
    print(f"  {'parameter':<10} {'true':>10} {'learned':>12} {'stderr':>10}")
    for name, value, se, _unit in model.parameters():
        try:
            true = truth[name]
        except vehs.Error:
            true = 0.0
        print(f"  {name:<10} {true:>10.4g} {value:>12.6g} {se:>10.2g}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="small ensembles (CI)")
    ap.add_argument("--out", default=os.path.join(REPO, "out", "python_pipeline"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    start = time.perf_counter()
    # --quick: cheaper parameter-uncertainty refits and no FPK reference curve in the diagnoses
    check = {"parameter_fit_samples": 5e5, "fpk": False} if args.quick else {}

    # -- 1. the paper's harvester (Eq. 27) simulated with its scheme (Eq. 30) ---------------------
    section("simulate the paper's penta-stable harvester (Eq. 27)")
    truth = vehs.Model.load(os.path.join(REPO, "data/paper/truth.json"))
    records = vehs.simulate(truth, trajectories=10 if args.quick else 100, duration=100, dt=0.001,
                            scheme="rk4_euler", seed=27, x0={"uniform": [-1.5, 1.5]})
    print(f"  {records}")

    # -- 2. identify from x(t) alone ---------------------------------------------------------
    section("identify drift and diffusion from x(t)")
    learned, report = vehs.identify(records)
    print(f"  estimator: {report['estimator']['used']}")
    table(learned, truth)

    # -- 3. diagnose the learned model ---------------------------------------------------------
    section("diagnose the learned model against the data")
    d = vehs.diagnose(learned, records, report=os.path.join(args.out, "paper_report"), label="paper", **check)
    print(f"  verdict {d.verdict}, score {d.score:.3g}; report {d.report}")

    fig, axes = plt.subplots(1, 3, figsize=(13, 3.5))
    vehs.plot.potential(learned, ax=axes[0], label="learned")
    vehs.plot.potential(truth, ax=axes[0], label="true", ls="--")
    axes[0].legend()
    vehs.plot.drift(learned, records, ax=axes[1])
    vehs.plot.diffusion(learned, records, ax=axes[2])
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "paper_model.png"), dpi=100)

    # -- 4. missing physics: friction hidden in the data, found by diagnose, added, refitted ----
    section("a harvester with hidden dry friction: baseline, diagnosis, refit with the suspect")
    friction_truth = vehs.Model.load(os.path.join(REPO, "data/missing_physics/truth.json"))
    data = vehs.simulate(friction_truth, trajectories=30 if args.quick else 100, duration=500, dt=0.01,
                         substeps=20, scheme="taylor15", seed=7, burn_in=50, record_velocity=False)
    v1, _ = vehs.identify(data)
    d1 = vehs.diagnose(v1, data, report=os.path.join(args.out, "friction_report"), label="v1: paper dictionaries", **check)
    print(f"  v1: verdict {d1.verdict}, score {d1.score:.3g}")
    for s in d1.suspects[:3]:
        z = f"{float(s['z']):5.1f}" if isinstance(s.get("z"), (int, float)) else "  n/a"
        print(f"     suspect {s['effect']:<22} {s['status']:<16} ({s['source']}), z {z}")
    top = d1.suspects[0]["effect"]
    v2, _ = vehs.identify(data, effects=[top])
    d2 = vehs.diagnose(v2, data, report=os.path.join(args.out, "friction_report"), label=f"v2: + {top}", **check)
    print(f"  v2 (+ {top}): verdict {d2.verdict}, score {d2.score:.3g}")
    table(v2, friction_truth)
    ax = vehs.plot.suspects(d1)
    ax.figure.savefig(os.path.join(args.out, "suspects.png"), dpi=100, bbox_inches="tight")

    # -- 5. the stationary response of the learned paper model, and power vs noise (Fig. 5a) ---
    section("stationary FPK of the learned model; E[Y^2] over 2D and 2Q (Fig. 5a)")
    s = vehs.stationary(learned, grid={"x": 400, "y": 400})
    print(f"  E[X^2] = {s.moments['E[X^2]']:.6f}, E[Y^2] = {s.moments['E[Y^2]']:.6f}")
    main_ax, _, _ = vehs.plot.density(s)
    main_ax.figure.savefig(os.path.join(args.out, "density.png"), dpi=100)
    axes = {"2D": [0.025, 0.04, 2], "2Q": [0.0, 0.03, 2]} if args.quick else {"2D": [0.01, 0.04, 7], "2Q": [0.0, 0.03, 7]}
    sw = vehs.sweep(learned, axes, grid={"x": 200, "y": 200})
    ax = vehs.plot.power(sw)
    ax.figure.savefig(os.path.join(args.out, "power_fig5a.png"), dpi=100)
    print(f"  {len(sw['points'])} sweep points, {sw['failed_points']} failed")
    print(f"\nfigures in {args.out} ({time.perf_counter() - start:.1f} s)")


if __name__ == "__main__":
    main()
