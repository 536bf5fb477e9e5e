"""vehs.diagnose's HTML report, as diagnose-vehs writes it: a driven rig (Duffing oscillator with
a base-acceleration input and sensor noise, from this file's own stochastic Heun stepper) opens
with the top card (verdict, next step, parameter table with standard errors and units) and shows
measured vs simulated with a fit percentage and the residual-input cross-correlation; an adequate
model has no failure section."""
import re

import numpy as np

import vehs

K1, K3, BETA, GAMMA, A22 = 2500.0, 300.0, 5.0, 800.0, 2000.0
DT, NOISE_SD = 0.002, 0.003


def driven_rig(n, seed):
    rng = np.random.default_rng(seed)
    freqs = np.linspace(2.0, 20.0, 12)
    phases = rng.uniform(0, 2 * np.pi, freqs.size)
    amp = np.sqrt(2.0 / freqs.size)
    sub = 10
    h = DT / sub
    t = np.arange(n * sub + 1) * h
    u_fine = amp * np.sin(2 * np.pi * np.outer(t, freqs) + phases).sum(axis=1)
    dw = np.sqrt(A22 * h) * rng.standard_normal(n * sub)
    x = np.empty(n)
    xs = ys = 0.0
    b2 = lambda x_, y_, u_: -K1 * x_ - K3 * x_ ** 3 - BETA * y_ + GAMMA * u_
    for i in range(n):
        x[i] = xs
        for s in range(sub):
            j = i * sub + s
            a0 = b2(xs, ys, u_fine[j])
            xp, yp = xs + ys * h, ys + a0 * h + dw[j]
            a1 = b2(xp, yp, u_fine[j + 1])
            xs, ys = xs + 0.5 * (ys + yp) * h, ys + 0.5 * (a0 + a1) * h + dw[j]
    return x + NOISE_SD * rng.standard_normal(n), u_fine[::sub][:n]


def test_the_report_opens_with_the_top_card_and_shows_measured_vs_simulated(tmp_path):
    x, u = driven_rig(30000, 5)
    model, _ = vehs.identify(x, dt=DT, u=u, drift_library=["x", "x^3", "y", "u"], diffusion_library=["1"])
    d = vehs.diagnose(model, x, dt=DT, u=u, report=tmp_path / "report", replicates=2, parameter_draws=2, fpk=False)
    html = open(d.report).read()
    first = html.find("<section")
    assert html[first:].startswith('<section id="top-card"')
    card = html[first:html.find("</section>", first)]
    assert re.search(r"Verdict: (ADEQUATE|INADEQUATE)", card)
    assert "Next step" in card
    assert "<th>parameter</th><th>value</th><th>standard error</th><th>unit</th>" in card
    assert re.search(r"<td>drift\[u\]</td><td>[^<]+</td><td>[0-9.e+-]+</td>", card)
    assert re.search(r"fit -?[0-9.]+ %", card)
    for fig in ("measured_vs_simulated", "residual_input_xcorr"):
        assert f'id="{fig}"' in html
    if d.verdict == "adequate":
        assert "Where the model fails" not in html
