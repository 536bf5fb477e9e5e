#!/usr/bin/env python3
"""identify's sampling rule on pentastable records with a y^2 diffusion (issue 13, the
velocity_dependent_noise loop; bench/results/diagnose_calibration_log.md): over seeds, the noise share eta the rule
reads from noise-free records (and how often it calls them noisy), then the sensor sd the noisy
estimator reads at stride 3 with 2 % white noise, against the truth. 32 records x 4000 samples at
dt 0.05, Taylor 1.5 with 20 substeps (as tests/diagnose/score_fixtures.hpp samples them).
  build/python-venv/bin/python bench/sampling_rule_state_dependent.py [SEEDS [SEED0]]
(the vehs package built by scripts/test.sh; about 1 CPU s a seed)."""
import sys

import numpy as np
import vehs

PENTA = {"x": -2.8125, "x^3": 5.215625, "x^5": -3.028125, "x^7": 0.675, "x^9": -0.05, "y": -0.1}
DIFF = {"1": 0.2, "y^2": 0.1}


def records(seed, trajectories=32, noise=0.0):
    truth = vehs.Model(drift=PENTA, diffusion=DIFF)
    return vehs.simulate(truth, trajectories=trajectories, duration=200.0, dt=0.05, substeps=20, scheme="taylor15",
                         seed=seed, burn_in=50.0, x0={"uniform": [-1, 1]}, sensor_noise=noise)


def sampling(r, **options):
    model, _ = vehs.identify(r, sparsity="none", drift_library=list(PENTA), diffusion_library=list(DIFF), **options)
    return model.to_dict()["sampling"]


def main():
    seeds = int(sys.argv[1]) if len(sys.argv) > 1 else 60
    seed0 = int(sys.argv[2]) if len(sys.argv) > 2 else 200
    eta, noisy, ratio = [], 0, []
    for seed in range(seed0, seed0 + seeds):
        s = sampling(records(seed))
        eta.append(s["noise_share"])
        noisy += s["verdict"] == "noisy"
        sd = 0.02 * float(np.std(np.asarray(records(seed + 1000003, trajectories=4).x)))
        n = sampling(records(seed, noise=sd), estimator="noisy", stride=3)
        ratio.append(n["sensor_noise_sd"] / sd if n["verdict"] == "noisy" else 0.0)
    eta, ratio = np.array(eta), np.array(ratio)
    print(f"noise-free, {seeds} seeds: eta {eta.mean():.4f} +- sd {eta.std():.4f} (max {eta.max():.4f}), "
          f"noisy {noisy} of {seeds}")
    print(f"2 % noise, stride 3: sd read / true {ratio.mean():.4f} +- sd {ratio.std():.4f} "
          f"({ratio.min():.4f}-{ratio.max():.4f}), noisy {int((ratio > 0).sum())} of {seeds}")


if __name__ == "__main__":
    main()
