"""sscape bodies in Blender: a panel (View3D > Sidebar > sscape) that makes a rigged body of the
default model or a loaded .sscape file, shaped by its components, its semantic sliders or made to
measure, in a named pose, at a level of detail. Blender's own exporters then give FBX or glTF.

Needs the sscape Python package (bindings/python) and libsscape.so: on Blender's Python path, or
the package's folder in the add-on's preferences or in SSCAPE_PYTHONPATH (docs/blender.md).
"""
import os
import sys

import bpy
from bpy.props import BoolProperty, CollectionProperty, EnumProperty, FloatProperty, FloatVectorProperty, StringProperty

bl_info = {
    "name": "sscape bodies",
    "author": "sscape",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > sscape",
    "description": "Rigged human bodies of sscape models: shape, sliders, made to measure, named poses, levels of detail",
    "category": "Add Mesh",
}

COMPONENTS = 10  # the whole-body components the panel shows


def _sscape():
    """The sscape package, found on the path, in SSCAPE_PYTHONPATH or in the add-on's preferences."""
    try:
        import sscape
        return sscape
    except ImportError:
        pass
    folders = [os.environ.get("SSCAPE_PYTHONPATH", "")]
    addon = bpy.context.preferences.addons.get(__name__)
    if addon is not None:
        folders.append(addon.preferences.package_path)
    for folder in folders:
        if folder and os.path.isdir(os.path.join(folder, "sscape")) and folder not in sys.path:
            sys.path.append(folder)
    import sscape  # ImportError names what is missing
    return sscape


class _Models:
    """Loaded models by path ("" the default), so the panel's lists and every body share one."""

    def __init__(self):
        self._loaded = {}

    def get(self, path):
        path = bpy.path.abspath(path) if path else ""
        if path not in self._loaded:
            sscape = _sscape()
            self._loaded[path] = sscape.Model.from_file(path) if path else sscape.Model()
        return self._loaded[path]


_models = _Models()


def _pose_items(self, context):
    try:
        return [(name, name, text) for name, text in _sscape().named_poses().items()]
    except Exception as error:  # the panel must draw even without the library
        return [("a_pose", "a_pose", str(error))]


def _level_items(self, context):
    try:
        model = _models.get(context.scene.sscape.model_path)
        return [(str(lv.index), f"{lv.name} ({lv.vertex_count} vertices)", "") for lv in model.levels]
    except Exception as error:
        return [("0", "full", str(error))]


class SscapeValue(bpy.types.PropertyGroup):
    name: StringProperty()
    unit: StringProperty()
    value: FloatProperty(precision=3)
    use: BoolProperty(name="Use", default=False)


class SscapeSettings(bpy.types.PropertyGroup):
    model_path: StringProperty(name="Model", description="A .sscape file; empty: the built-in default model", subtype="FILE_PATH")
    shape_by: EnumProperty(name="Shape by", items=[
        ("COMPONENTS", "Components", "the first whole-body shape components, in standard deviations"),
        ("SLIDERS", "Sliders", "semantic sliders (stature, mass, ...): the population's typical body with those values"),
        ("MEASURE", "Made to measure", "the measurements ticked, reproduced by the shape")])
    components: FloatVectorProperty(name="Components", size=COMPONENTS, min=-4.0, max=4.0, default=[0.0] * COMPONENTS)
    sliders: CollectionProperty(type=SscapeValue)
    measurements: CollectionProperty(type=SscapeValue)
    pose: EnumProperty(name="Pose", items=_pose_items)
    hands: FloatProperty(name="Hands closed", min=0.0, max=1.0, default=0.0)
    level: EnumProperty(name="Level of detail", items=_level_items)


class SSCAPE_OT_load_model(bpy.types.Operator):
    """Loads the model and lists its sliders and the measurements at the population's mean"""
    bl_idname = "sscape.load_model"
    bl_label = "Load model"

    def execute(self, context):
        settings = context.scene.sscape
        try:
            model = _models.get(settings.model_path)
            from sscape.body import measurement_names
            mean = _sscape().Body(model).measure()
        except Exception as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        settings.sliders.clear()
        for s in model.sliders:
            item = settings.sliders.add()
            item.name, item.unit, item.value = s.name, s.unit, s.mean
        settings.measurements.clear()
        for name in measurement_names():
            item = settings.measurements.add()
            item.name, item.value = name, mean[name]
        return {"FINISHED"}


def shaped_body(settings):
    """A Body of the settings' model with their shape and pose (what the operator builds from)."""
    sscape = _sscape()
    model = _models.get(settings.model_path)
    body = sscape.Body(model)
    if settings.shape_by == "COMPONENTS":
        body.shape = list(settings.components)[:model.shape_count]
    elif settings.shape_by == "SLIDERS":
        if len(settings.sliders) == 0:
            raise ValueError("no sliders: press Load model first")
        body.set_sliders({s.name: s.value for s in settings.sliders})
    else:
        targets = {m.name: m.value for m in settings.measurements if m.use}
        if not targets:
            raise ValueError("made to measure: tick at least one measurement (Load model lists them)")
        if not body.make_to_measure(targets):
            print("sscape: not every measurement was reached within 0.5 mm (an unusual combination)")
    body.set_pose(model.named_pose(settings.pose, settings.hands, settings.hands))
    return model, body


class SSCAPE_OT_create_body(bpy.types.Operator):
    """Adds a rigged body: an armature in the chosen pose and the mesh of the chosen level of detail"""
    bl_idname = "sscape.create_body"
    bl_label = "Create body"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        from . import rig
        settings = context.scene.sscape
        try:
            model, body = shaped_body(settings)
            armature, mesh = rig.make_body(context, model, body, int(settings.level))
        except Exception as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, f"{len(mesh.data.vertices)} vertices, {len(armature.data.bones)} bones")
        return {"FINISHED"}


class SSCAPE_PT_panel(bpy.types.Panel):
    bl_label = "sscape body"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "sscape"

    def draw(self, context):
        settings, layout = context.scene.sscape, self.layout
        layout.prop(settings, "model_path")
        layout.operator("sscape.load_model")
        layout.prop(settings, "shape_by")
        if settings.shape_by == "COMPONENTS":
            layout.prop(settings, "components")
        else:
            values = settings.sliders if settings.shape_by == "SLIDERS" else settings.measurements
            for item in values:
                row = layout.row()
                if settings.shape_by == "MEASURE":
                    row.prop(item, "use", text="")
                row.prop(item, "value", text=f"{item.name} {item.unit}".strip())
        layout.prop(settings, "pose")
        layout.prop(settings, "hands")
        layout.prop(settings, "level")
        layout.operator("sscape.create_body")


class SscapePreferences(bpy.types.AddonPreferences):
    bl_idname = __name__
    package_path: StringProperty(name="sscape Python package folder", description="bindings/python of an sscape checkout",
                                 subtype="DIR_PATH")

    def draw(self, context):
        self.layout.prop(self, "package_path")


_classes = (SscapeValue, SscapeSettings, SSCAPE_OT_load_model, SSCAPE_OT_create_body, SSCAPE_PT_panel, SscapePreferences)


def register():
    for c in _classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.sscape = bpy.props.PointerProperty(type=SscapeSettings)


def unregister():
    del bpy.types.Scene.sscape
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
