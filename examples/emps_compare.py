"""The EMPS comparison of `make demo` step 1 from Python: the rigid-body model against the real ball-screw stage,
refit, diagnosed, plotted. Run after the build, from the repository:

    PYTHONPATH=build/release/python python3 examples/emps_compare.py
"""

import pathlib

import motionblocks as mb

emps = pathlib.Path(__file__).resolve().parents[1] / "diagrams" / "emps"
outcome = mb.compare(mb.Diagram.load(emps / "rigid_body.json"), emps / "data" / "DATA_EMPS.csv")

print(f"{outcome.output}: RMSE {outcome.rmse_before:.3f} -> {outcome.rmse_after:.3f} {outcome.unit}")
for p in outcome.parameters:
    print(f"  {p.name:<18} {p.estimate:10.4g}  95 % [{p.interval[0]:.4g}, {p.interval[1]:.4g}]")
for e in outcome.diagnosis[:3]:
    print(f"  missing? {e.effect:<28} {100 * e.score:5.1f} %")

try:
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib not installed (apt install python3-matplotlib): no plot")
else:
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(10, 6))
    top.plot(outcome.time, outcome.measured, label="measured", lw=0.6)
    top.plot(outcome.time, outcome.model, label="model, refit", lw=0.6)
    top.set_ylabel(f"force [{outcome.unit}]")
    top.legend()
    bottom.plot(outcome.time, outcome.measured - outcome.model, lw=0.5)
    bottom.set_ylabel(f"residual [{outcome.unit}]")
    bottom.set_xlabel("time [s]")
    fig.suptitle(f"EMPS: {outcome.diagnosis[0].effect} is what the model misses")
    fig.savefig("emps_compare.png", dpi=120)
    print("wrote emps_compare.png")
