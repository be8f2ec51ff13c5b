"""The default case's figure from Python: the paper's academic model
(N = 24, traveling wave h = 1 of 4 N, R-HBM), its forced response per
sector against the linear response, and the cyclic components at the
peak (the figures `cyclorub run` draws in plots/).

    pip install matplotlib
    python default_case_figure.py            # writes default_case.png

Written as notebook cells (# %%): run them one by one in Jupyter or VS Code.
"""

# %% Solve the default case (about 0.2 s; the stability check is skipped
# here: it costs far more than the curve, see docs/stability.md).
import matplotlib.pyplot as plt
import numpy as np

import cyclorub

case = cyclorub.Case.default()
result = case.run(stability=False)
print(result)
print(f"{len(result)} points, {result.basis['unknowns']} unknowns on the "
      f"{result.basis['kind']} basis, solved in {result.timings['solve_s']:.3f} s")

# %% The forced response: the observed dof (the blade tip m1) on sector 1,
# nonlinear (solid) against linear (dotted); a traveling wave moves every
# sector alike.
hz = result.frequency_hz
amplitude = result.amplitude                  # [point, sector], m
linear_hz, linear = result.linear_response()  # [f], [f, sector]
gap = case.casing.gap

fig, (ax, bars) = plt.subplots(1, 2, figsize=(11, 4.2))
ax.plot(hz, amplitude[:, 0] / gap, label="nonlinear (contact)")
ax.plot(linear_hz, linear[:, 0] / gap, ":", label="linear (no casing)")
ax.axhline(1.0, color="grey", lw=0.8, label="gap")
ax.set_xlabel("excitation frequency (Hz)")
ax.set_ylabel("largest displacement toward the casing / gap")
ax.set_ylim(0, 1.5 * (amplitude.max() / gap))
ax.set_title("N = 24, traveling wave h = 1, R-HBM")
ax.legend()

# %% The cyclic components of the observed dof at the peak, per harmonic
# and nodal diameter, forward and backward (log scale).
peak = int(np.argmax(amplitude[:, 0]))
forward, backward = result.forward[peak], result.backward[peak]  # [harmonic, ND]
# The pairs that hold the motion (the rest is round-off).
harmonics, diameters = np.nonzero(np.maximum(forward, backward) > 1e-9 * backward.max())
labels = [f"k={k}, d={d}" for k, d in zip(harmonics, diameters)]
x = np.arange(len(labels))
bars.bar(x - 0.2, backward[harmonics, diameters], 0.4, label="backward")
bars.bar(x + 0.2, forward[harmonics, diameters], 0.4, label="forward")
bars.set_yscale("log")
bars.set_xticks(x, labels, rotation=60, fontsize=8)
bars.set_ylabel("component (m)")
bars.set_title(f"cyclic components at {hz[peak]:.2f} Hz")
bars.legend()
fig.tight_layout()
fig.savefig("default_case.png", dpi=150)
print("wrote default_case.png")
