"""A first Python session with motionblocks, cell by cell ("# %%" cells: VS Code, Spyder, or Jupyter through
jupytext; or run it whole). From the repository root, after a build (`make demo` builds build/release):

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python_session.py

It needs Debian's python3-numpy and python3-pandas (`make deps` installs them). Units are SI throughout."""

# %% A diagram: a PD position loop around a rigid body, the body inside the subsystem "plant"
import motionblocks as mb

d = mb.Diagram.load("diagrams/hil/pd_rigid_body.json")
print(d)
print([b["name"] for b in d.blocks()])
print("kp =", d.get("controller.kp"), "N/m")  # one dotted key, as set() takes it; SI units

# %% Stiffer gains, and a signal the diagram does not log: the body's velocity, inside the subsystem
d.set("controller.kp", 2 * d.get("controller.kp"))
d.set("controller.kd", 100.0)
r = mb.simulate(d, log=["plant/body.v"])  # for this run only; the diagram is unchanged
print(r)  # the span, the signals with their units, the metrics
print(r.keys())
print(r.units)

# %% The run as a pandas DataFrame: index time_s [s], one column per signal, the units in df.attrs
df = r.to_pandas()
print(df.head())
print(df.attrs["units"])
print(df[["tracking_error", "plant/body.v"]].abs().max())
print(f"tracking RMSE {r.metrics['tracking_rmse'] * 1e6:.1f} µm")

# %% A model against a real measurement: the EMPS ball-screw stage (README, demo step 1)
c = mb.compare(mb.Diagram.load("diagrams/emps/rigid_body.json"), "diagrams/emps/data/DATA_EMPS.csv")
print(c)  # RMSE and fit before and after the refit, the top missing effect
for p in c.parameters:
    print(" ", p)
for e in c.diagnosis[:3]:
    print(" ", e)

# %% Measured, model and residual over time: index time_s [s], columns in N
cdf = c.to_pandas()
print(cdf.describe().loc[["mean", "std", "max"]])
window = (cdf.index // 5) * 5  # 5 s windows
rms = (cdf["force.residual"] ** 2).groupby(window).mean() ** 0.5
print(rms.rename(f"residual RMS [{cdf.attrs['units']['force.residual']}] per 5 s from").round(2))

# %% A sweep of the stiffness: one row per run
rows = mb.sweep(mb.Diagram.load("diagrams/hil/pd_rigid_body.json"),
                {"grid": {"controller.kp": [5000.0, 9300.0, 18600.0]}}, jobs=2)
print(rows)
print(rows.to_pandas()[["controller.kp", "tracking_rmse", "tracking_max"]])
