"""A body of an sscape model as Blender objects: the shaped mesh at rest (one level of detail) with
its UVs and skin weights as vertex groups, and an armature posed to the body's pose. Blender's own
armature deformation (linear blend skinning, as the library's) then gives the library's posed body.

No user interface here: the add-on's operator and the headless test both call make_body.
"""
import bpy
import numpy as np
from mathutils import Matrix, Quaternion, Vector


def _bone_tails(heads, parents):
    """Each bone points at the mean of its children's heads, or continues its parent's direction
    (a third of its parent's length) at a leaf; at least 1 cm, which Blender needs to keep a bone."""
    J = len(heads)
    tails = np.zeros_like(heads)
    children = [[] for _ in range(J)]
    for j, p in enumerate(parents):
        if p >= 0:
            children[p].append(j)
    for j in range(J):  # parents precede children, so a leaf's parent is done first
        if children[j]:
            tip = heads[children[j]].mean(axis=0)
        elif parents[j] >= 0:
            p = parents[j]
            direction = heads[j] - heads[p]
            tip = heads[j] + direction / 3.0
        else:
            tip = heads[j] + np.array([0.0, 0.0, 0.1])
        if np.linalg.norm(tip - heads[j]) < 0.01:
            up = tails[parents[j]] - heads[parents[j]] if parents[j] >= 0 else np.array([0.0, 0.0, 1.0])
            tip = heads[j] + 0.01 * up / max(np.linalg.norm(up), 1e-9)
        tails[j] = tip
    return tails


def make_body(context, model, body, level=0, name="sscape_body"):
    """Adds an armature object (the model's joints, posed as the body) with the body's mesh as its
    child (level: a level of detail by index or name, 0 the full mesh). Returns (armature, mesh).
    The library is Y up; Blender is Z up: the armature object turns it (+90 degrees about X)."""
    lv = model.level(level)
    names, parents = model.joint_names, [int(p) for p in model.joint_parents]
    inverse_bind = body.inverse_bind_matrices.astype(np.float64)   # (J, 4, 4) rows
    skinning = body.skinning_matrices.astype(np.float64)           # world x inverse bind
    heads = np.array([np.linalg.inv(m)[:3, 3] for m in inverse_bind])
    tails = _bone_tails(heads, parents)

    armature = bpy.data.armatures.new(name + "_rig")
    rig = bpy.data.objects.new(name, armature)
    rig.matrix_world = Matrix.Rotation(np.pi / 2, 4, "X")
    context.collection.objects.link(rig)
    context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    bones = []
    for j, joint in enumerate(names):
        b = armature.edit_bones.new(joint)
        b.head, b.tail = Vector(heads[j]), Vector(tails[j])
        if parents[j] >= 0:
            b.parent = bones[parents[j]]
        bones.append(b)
    bpy.ops.object.mode_set(mode="OBJECT")

    # Pose: with B_j a bone's rest frame and S_j the library's skinning rotation, Blender's posed
    # bone frame must be S_j B_j, so its rotation is B_j^T S_parent^T S_j B_j and the root's
    # location moves its head where the library's root went.
    for j, joint in enumerate(names):
        B = np.array(armature.bones[joint].matrix_local.to_3x3())
        S = skinning[j, :3, :3]
        Sp = skinning[parents[j], :3, :3] if parents[j] >= 0 else np.eye(3)
        pb = rig.pose.bones[joint]
        pb.rotation_mode = "QUATERNION"
        pb.rotation_quaternion = Matrix((B.T @ Sp.T @ S @ B).tolist()).to_quaternion()
        if parents[j] < 0:
            moved = skinning[j, :3, :3] @ heads[j] + skinning[j, :3, 3]
            pb.location = Vector(B.T @ (moved - heads[j]))

    # The mesh at rest, its face-corner UVs, its skin as vertex groups, deformed by the armature.
    rest = body.level_rest_vertices(lv.index).astype(np.float64)
    triangles = model.level_triangles(lv.index)
    mesh = bpy.data.meshes.new(name + "_mesh")
    mesh.from_pydata(rest.tolist(), [], triangles.tolist())
    uvs = model.level_uvs(lv.index)
    if uvs is not None:
        coordinates, corner = uvs
        layer = mesh.uv_layers.new(name="UVMap")
        layer.data.foreach_set("uv", coordinates[corner.reshape(-1)].reshape(-1))
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    mesh.update()
    obj = bpy.data.objects.new(name + "_mesh", mesh)
    context.collection.objects.link(obj)
    obj.parent = rig
    joints, weights = model.level_skin(lv.index)
    groups = [obj.vertex_groups.new(name=joint) for joint in names]
    for v in range(lv.vertex_count):
        for k in range(4):
            if weights[v, k] > 0:
                groups[joints[v, k]].add([v], float(weights[v, k]), "REPLACE")
    modifier = obj.modifiers.new("Armature", "ARMATURE")
    modifier.object = rig
    material = bpy.data.materials.get("sscape_skin") or bpy.data.materials.new("sscape_skin")
    material.diffuse_color = (0.80, 0.62, 0.52, 1.0)
    mesh.materials.append(material)
    return rig, obj
