# %% [markdown]
# # lgvi from Python: a quick start
#
# A notebook in the "percent" format (cells start with `# %%`; VS Code and Spyder run the cells as
# they are); quick_start.ipynb beside it is the same notebook for Jupyter, written from this file
# by python/percent_to_notebook.py. As a script:
#
#     PYTHONPATH=build/python python3 examples/python/quick_start.py
#
# ctest `python_tests` runs this file and checks the .ipynb is up to date; ctest
# `notebook_quick_start` executes the .ipynb in a Jupyter kernel (nbclient).

# %%
import tempfile

import numpy as np

import lgvi

# %% [markdown]
# ## A scene of your own
# The tables of a scene file (experiments/scene/scene.hpp) as dicts: a heavy top, the paper's 3D
# pendulum (centre of mass 0.3 m from the pivot along e3) spun fast about e3, tilted 0.1 rad.

# %%
top = lgvi.make_scene(
    "pendulum",
    parameters={"mass": 1.0, "inertia": [0.13, 0.28, 0.17], "rho": [0.0, 0.0, 0.3], "gravity": 9.81},
    initial={"R": lgvi.so3.exp(np.array([0.1, 0.0, 0.0])), "Omega": [0.0, 0.0, 20.0]},
    h=1e-3, t_final=2.0, output_every=10, name="my-top")
print(top)

# %% [markdown]
# ## The LGVI: numpy arrays and the run's summary as a dict

# %%
run = lgvi.simulate(top)
print(run["t"].shape, run["R"].shape, run["Omega"].shape)
s = run["summary"]
print(f"max |E - E0| / |E0| = {s['max_energy_error_relative']:.2e}, "
      f"max ||R^T R - I|| = {s['max_orthogonality_error']:.1e}, {s['wall_seconds'] * 1e3:.1f} ms")
# The vertical angular momentum e3^T R J Omega is conserved by the LGVI (symmetry about gravity).
vertical = np.einsum("nj,nj->n", run["R"][:, 2, :], run["Omega"] * np.array([0.13, 0.28, 0.17]))
print(f"vertical momentum drift {np.abs(vertical - vertical[0]).max():.1e}")

# %% [markdown]
# ## A baseline on the same scene, and the methods there are

# %%
cvode = lgvi.simulate(top, method="cvode-bdf", model="quaternion", rtol=1e-10)
print("final attitude difference LGVI vs CVODE:", np.linalg.norm(run["R"][-1] - cvode["R"][-1]))
print([m["name"] for m in lgvi.methods()])

# %% [markdown]
# ## A shipped scene, its horizon shortened; the CSV kept

# %%
with tempfile.TemporaryDirectory() as tmp:
    dumbbell = lgvi.load_scene("dumbbell", t_final=1.0)
    orbit = lgvi.simulate(dumbbell, method="lgvi-yoshida4", csv=f"{tmp}/dumbbell.csv")
    print(dumbbell, orbit["x"][-1], orbit["metadata"]["units"])

# %% [markdown]
# ## Optimal control: indirect (the pendulum transfer) and direct (the cart-pendulum, IPOPT)

# %%
transfer = lgvi.solve_ocp("pendulum", form="symmetric", steps=100)
print(transfer["summary"]["status_detail"])
cart = lgvi.solve_ocp("cart-pendulum", solver="ipopt")  # the paper's 7 knots per control, h = 0.01
print(cart["summary"]["status_detail"], cart["trajectory"]["t"].shape)

# %% [markdown]
# ## Your own potential, written in Python
# A body in a uniform field B with a magnetic dipole m (body frame): U(R) = -B^T R m and its
# moment M(R) = m x R^T B (eq. 13). Every method that takes the system `potential-body` runs it.

# %%
B, m = np.array([0.05, 0.0, 0.1]), np.array([0.0, 0.0, 2.0])
mine = lgvi.potential_scene([0.13, 0.28, 0.17], lambda R: -B @ R @ m, lambda R: np.cross(m, R.T @ B),
                            {"Omega": [0.5, 1.0, 3.0]}, h=0.005, t_final=5.0, output_every=10)
for method, model in (("lgvi", None), ("rkmk4", None), ("odeint-rk4", "quaternion")):
    s = lgvi.simulate(mine, method=method, model=model)["summary"]
    print(f"{method:12s} max |E - E0| / |E0| = {s['max_energy_error_relative']:.1e}, "
          f"field-axis momentum drift {s['max_momentum_drift']:.1e}")

# %% [markdown]
# ## Optimal control of a scene of yours, with another weight, and a study

# %%
slew = lgvi.load_scene("ocp-free-body-slew")
for W in ([1.0, 1.0, 1.0], [1.0, 1.0, 10.0]):
    s = lgvi.solve_ocp(slew, W=W, steps=200)["summary"]
    print(f"W = diag{tuple(W)}: cost {s['cost']:.4g}, violation {s['violation']:.1e}")
with tempfile.TemporaryDirectory() as tmp:
    rows = lgvi.run_study("spacecraft-tumble", tmp, quick=True, jobs=2)  # a shipped study, its quick form
best = min((r for r in rows if r["status"] == "completed"), key=lambda r: r["final_error"])
print(f"{len(rows)} cases of the spacecraft-tumble study; the most accurate: {best['case']}, "
      f"final error {best['final_error']:.1e} in {best['wall_seconds'] * 1e3:.2f} ms")

# %% [markdown]
# ## A suite and the regression gate

# %%
print([name for name, _ in lgvi.suites()])
with tempfile.TemporaryDirectory() as tmp:
    rows = lgvi.run_suite("default", tmp, jobs=2)  # every shipped scene, both LGVI forms
for r in rows:
    print(f"{r['case']:32s} {r['status']:10s} max |E - E0| = {r['max_energy_error_absolute']:.1e}")
report = lgvi.validate(quick=True, only=["exact"])
print(report["table"].splitlines()[-1])
