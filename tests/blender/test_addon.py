"""Headless test of the Blender add-on (bindings/blender/sscape_body) and of Blender's import of
sscape's GLB files. Run by ctest:
  blender -b --factory-startup --python-exit-code 1 --python tests/blender/test_addon.py -- OUT_DIR [GLB]
with the sscape package on PYTHONPATH and SSCAPE_LIBRARY set. Any failed check raises.
"""
import os
import sys

import bpy
import numpy as np
from mathutils import Matrix

args = sys.argv[sys.argv.index("--") + 1:]
out_dir, glb = args[0], (args[1] if len(args) > 1 else None)
os.makedirs(out_dir, exist_ok=True)
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "bindings", "blender"))

import sscape  # noqa: E402
import sscape_body  # noqa: E402


def clear():
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)


def posed_world(mesh_object):
    """The mesh's vertices after Blender's armature deformation, world frame."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = mesh_object.evaluated_get(depsgraph).to_mesh()
    v = np.empty(3 * len(evaluated.vertices))
    evaluated.vertices.foreach_get("co", v)
    m = np.array(mesh_object.matrix_world)
    v = v.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
    mesh_object.evaluated_get(depsgraph).to_mesh_clear()
    return v


def check_body(settings, level, expect_vertices=None):
    """Creates a body with the panel's operator; it must match the library's body for the same settings."""
    clear()
    settings.level = str(level)
    assert bpy.ops.sscape.create_body() == {"FINISHED"}
    rig = next(o for o in bpy.data.objects if o.type == "ARMATURE")
    mesh = next(o for o in bpy.data.objects if o.type == "MESH")
    model, body = sscape_body.shaped_body(settings)
    lv = model.level(level)
    assert len(mesh.data.vertices) == lv.vertex_count, (len(mesh.data.vertices), lv.vertex_count)
    assert len(mesh.data.polygons) == lv.triangle_count
    assert len(rig.data.bones) == model.joint_count
    assert sorted(b.name for b in rig.data.bones) == sorted(model.joint_names)
    # Blender's skinning of the rig gives the library's posed body (Y up turned to Blender's Z up).
    library = body.level_vertices(level).astype(np.float64) @ np.array(Matrix.Rotation(np.pi / 2, 3, "X")).T
    error = np.linalg.norm(posed_world(mesh) - library, axis=1)
    print(f"level {lv.name}: {lv.vertex_count} vertices, {len(rig.data.bones)} bones; Blender's posed body against "
          f"the library's: {error.mean() * 1e3:.4f} mm mean, {error.max() * 1e3:.4f} mm worst")
    assert error.max() < 1e-4, error.max()
    if expect_vertices is not None:
        assert lv.vertex_count == expect_vertices
    return rig, mesh, body


sscape_body.register()
settings = bpy.context.scene.sscape
assert bpy.ops.sscape.load_model() == {"FINISHED"}
names = [s.name for s in settings.sliders]
assert names == [s.name for s in sscape.Model().sliders], names
assert len(settings.measurements) == len(sscape.body.measurement_names())

# Components, a named pose, the full mesh.
settings.shape_by = "COMPONENTS"
settings.components = [1.5, -1.0, 0.5, 0, 0, 0, 0, 0, 0, 0]
settings.pose = "sitting"
settings.hands = 0.5
rig, mesh, body = check_body(settings, 0, 13380)
assert abs(body.shape[0] - 1.5) < 1e-6

# Sliders, another pose, the smallest level.
settings.shape_by = "SLIDERS"
next(s for s in settings.sliders if s.name == "stature").value = 1.88
settings.pose = "arms_raised"
_, _, body = check_body(settings, len(sscape.Model().levels) - 1)
assert abs(body.sliders["stature"] - 1.88) < 0.01, body.sliders["stature"]

# Made to measure, a middle level; then FBX out and back in.
settings.shape_by = "MEASURE"
for m in settings.measurements:
    if m.name in ("stature", "waist_girth"):
        m.use, m.value = True, {"stature": 1.62, "waist_girth": 0.9}[m.name]
settings.pose = "t_pose"
rig, mesh, body = check_body(settings, 1)
assert abs(body.measure()["waist_girth"] - 0.9) < 0.002
fbx = os.path.join(out_dir, "body.fbx")
assert bpy.ops.export_scene.fbx(filepath=fbx, use_selection=False, add_leaf_bones=False) == {"FINISHED"}
assert os.path.getsize(fbx) > 100_000
clear()
assert bpy.ops.import_scene.fbx(filepath=fbx) == {"FINISHED"}
imported = {o.type: o for o in bpy.data.objects}
assert len(imported["ARMATURE"].data.bones) == body.model.joint_count
assert len(imported["MESH"].data.vertices) == body.model.level(1).vertex_count
print(f"FBX {os.path.getsize(fbx)} bytes: written and read back, {len(imported['ARMATURE'].data.bones)} bones, "
      f"{len(imported['MESH'].data.vertices)} vertices")

# A model that is not there: an error in the operator's report, nothing added.
clear()
settings.model_path = os.path.join(out_dir, "missing.sscape")
try:  # in the background an operator's error report is raised
    bpy.ops.sscape.create_body()
    raise AssertionError("a missing model made a body")
except RuntimeError as error:
    assert "missing.sscape" in str(error), error
assert len(bpy.data.objects) == 0
settings.model_path = ""

# sscape's GLB through Blender's glTF importer: every level a mesh, every morph a shape key.
if glb:
    if "bool" not in vars(np):
        np.bool = bool  # Blender 3.4's importer still uses numpy.bool, gone in numpy 1.24 (docs/blender.md)
    clear()
    assert bpy.ops.import_scene.gltf(filepath=glb) == {"FINISHED"}
    meshes = sorted((o for o in bpy.data.objects if o.type == "MESH"), key=lambda o: o.name)
    levels = sscape.Model().levels
    assert len(meshes) == len(levels), [o.name for o in meshes]
    for o, lv in zip(meshes, levels):
        keys = o.data.shape_keys.key_blocks
        assert o.name.endswith(f"_LOD{lv.index}"), o.name
        assert len(o.data.polygons) == lv.triangle_count
        assert [k.name for k in keys][1:] == [f"component_{k + 1}" for k in range(len(keys) - 1)] and len(keys) > 1
    arm = next(o for o in bpy.data.objects if o.type == "ARMATURE")
    print(f"glTF import: {len(meshes)} levels, {len(keys) - 1} shape keys each, {len(arm.data.bones)} bones")
sscape_body.unregister()
print("blender add-on test: passed")
