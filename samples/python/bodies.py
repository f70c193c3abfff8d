"""sscape from Python, step by step: the default model, bodies by shape, by sliders and by pose,
their measurements, and files for other tools.

    python3 samples/python/bodies.py OUT_DIR      (with the package installed, or
    SSCAPE_LIBRARY=build/sdk/libsscape.so PYTHONPATH=bindings/python python3 samples/python/bodies.py OUT_DIR)
"""
import sys
from pathlib import Path

import numpy as np

import sscape

out = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
out.mkdir(parents=True, exist_ok=True)

# %% The model: what it holds.
model = sscape.Model()
print(model)
print("sliders:", ", ".join(f"{s.name} ({s.unit or '-'}, {s.minimum:.2f} to {s.maximum:.2f})" for s in model.sliders))

# %% A body by its shape coefficients (standard deviations of the population).
body = sscape.Body(model)
body.shape = [2.0, 0.0, -1.0]
m = body.measure()
print(f"shape [2, 0, -1]: stature {m['stature']:.3f} m, waist {m['waist_girth']:.3f} m, mass {m['mass']:.1f} kg")

# %% By what people understand: sliders, in SI units.
body.shape = np.zeros(model.shape_count)
body.set_slider("stature", 1.85)
body.set_slider("mass", 90.0)
print("sliders now:", {k: round(v, 3) for k, v in body.sliders.items()})

# %% Posed: the left elbow bent 60 degrees about x; the body's vertices as one (V, 3) array.
rotations = np.tile(np.array([0, 0, 0, 1], np.float32), (model.joint_count, 1))
half = np.radians(60) / 2
rotations[model.joint_names.index("lowerarm_l")] = [np.sin(half), 0, 0, np.cos(half)]
body.set_pose(rotations)
v = body.vertices
print(f"posed body: {v.shape[0]} vertices, {np.ptp(v[:, 1]):.3f} m tall, lowest point y = {v[:, 1].min():.3f} m")

# %% Files: OBJ for any tool, rigged glTF for engines and Blender.
body.write(out / "sample_body.obj")
body.write(out / "sample_body.glb")
print("wrote", out / "sample_body.obj", "and", out / "sample_body.glb")
body.close()
