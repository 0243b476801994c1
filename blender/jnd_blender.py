"""jnd in Blender: the smallest texture sizes and the LOD chain nobody notices, for the selected object.

A panel in the 3D viewport's sidebar (N, tab "jnd"): choose the screen and
the criterion, "Run texres" exports the selected object with Blender's own
glTF exporter (GLB, selection only) to a temporary folder and runs
``jnd.texres`` on it through jnd's Python package (python/, built into
build/python); the panel then shows P, the memory before and after and the
chosen size of each image, and "Apply" scales the object's images to those
sizes (Image.scale; the scaled pixels are packed into the .blend, the image
files on disk are never written).

"Run lod" exports the object the same way and runs ``jnd.lod`` on it with
the screen as its one target screen: the panel shows each level's
triangles, the perceptual choice (the coarsest level nobody notices at the
viewing condition, the criterion's P and Q) and each level's switch
distance. "Apply LOD" imports the GLB jnd wrote (every level, MSFT_lod)
into a collection "<object> LOD", one object per level named
"<object>_LOD<k>", parented to the object (levels 1.. hidden), each with
the custom properties jnd_lod_level, jnd_triangles and
jnd_switch_distance (object units; -1: never). The object itself is left
as it is.

Where the package is: the add-on's preference "jnd Python folder", else
the environment variable JND_PYTHONPATH (the folder that holds jnd/, e.g.
build/python). Blender's Python must be the one the package was built for
(Debian's blender 3.4 uses the system's python3.11).
"""
import json
import os
import sys
import tempfile
import threading

import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

bl_info = {
    "name": "jnd: texture sizes nobody notices",
    "author": "jnd",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > jnd",
    "description": "Runs jnd texres or lod on the selected object and applies the chosen sizes or levels",
    "category": "Object",
}

PROP = "jnd_texres"   # the object's custom property: the last run's summary (JSON)
LOD_PROP = "jnd_lod"  # ... and the last lod run's
BUDGET_PROP = "jnd_budget"  # ... and the last budget run's
MIB = 1048576.0


def _jnd():
    """The jnd package, from the add-on's preference or JND_PYTHONPATH."""
    prefs = bpy.context.preferences.addons.get(__name__)
    path = (prefs.preferences.python_path if prefs else "") or os.environ.get("JND_PYTHONPATH", "")
    if path and path not in sys.path:
        sys.path.insert(0, bpy.path.abspath(path))
    import jnd
    return jnd


def _off_main_thread(call):
    """call() on a thread of its own, waited for; its result, or its
    exception raised here. Blender's window keeps its GLX context current on
    the main thread, and jnd's renderer then gets no EGL context there ("no
    OpenGL 4.5 core context"); a thread without a current context gets one.
    The library releases the GIL, so nothing else is held meanwhile."""
    box = {}

    def run():
        try:
            box["result"] = call()
        except BaseException as e:   # re-raised on the caller's thread
            box["error"] = e

    t = threading.Thread(target=run, name="jnd")
    t.start()
    t.join()
    if "error" in box:
        raise box["error"]
    return box["result"]


def _decimal(x):
    """A FloatProperty's value (single precision: 0.2 is 0.20000000298) as
    the decimal the user typed, so that the report says p 0.2 as the command's."""
    return float(f"{x:.6g}")


_presets = []   # Blender needs the enum's strings kept alive


def _display_items(self, context):
    if not _presets:
        try:
            names = _jnd().display_presets()
        except ImportError:
            names = ["standard-fhd"]
        _presets.extend((n, n, f"jnd's display preset {n}") for n in names)
    return _presets


class JndPreferences(bpy.types.AddonPreferences):
    bl_idname = __name__
    python_path: StringProperty(name="jnd Python folder", subtype="DIR_PATH",
                                description="The folder that holds the jnd package (build/python); "
                                            "empty: $JND_PYTHONPATH")

    def draw(self, context):
        self.layout.prop(self, "python_path")


class JndSettings(bpy.types.PropertyGroup):
    display: EnumProperty(name="Screen", items=_display_items, description="The display the asset is seen on")
    p: FloatProperty(name="P", default=0.2, min=1e-6, max=1 - 1e-6,
                     description="A view is above when its pooled probability of detection exceeds P")
    q: FloatProperty(name="Q", default=0.1, min=0, max=0.999,
                     description="At most this fraction of the views may be above P")
    views: IntProperty(name="Views", default=8, min=1, max=4096, description="Views sampled around the object")
    view_size: IntProperty(name="View size", default=384, min=16, max=16384,
                           description="Side of each rendered view, pixels")
    confirm: IntProperty(name="Confirm rounds", default=2, min=0, max=16,
                         description="Fresh sets of views the choice must then hold on")
    min_size: IntProperty(name="Min size", default=32, min=1, max=32768,
                          description="Floor of the candidate sizes, pixels")
    lod_errors: StringProperty(name="Errors", default="",
                               description="The chain's error targets, fractions of the object's extent, "
                                           "rising (e.g. 1/256,1/64,1/16); empty: jnd's default")
    lod_views: IntProperty(name="LOD views", default=2, min=1, max=4096,
                           description="Views of 003's analysis (the judge's are Views)")
    budget_memory: FloatProperty(name="Memory MiB", default=0, min=0, max=1e6,
                                 description="Budget: the most texture memory, MiB (block formats and mips); "
                                             "0: no bound (with no triangle bound either: the cheapest "
                                             "choice nobody notices)")
    budget_triangles: IntProperty(name="Triangles", default=0, min=0, max=2000000000,
                                  description="Budget: the most triangles of the finest level; 0: no bound")


def _upstream_image(socket, seen=None):
    """The image of the first Image Texture node upstream of socket."""
    seen = seen if seen is not None else set()
    for link in socket.links:
        node = link.from_node
        if node in seen:
            continue
        seen.add(node)
        if node.type == "TEX_IMAGE" and node.image:
            return node.image
        for s in node.inputs:
            im = _upstream_image(s, seen)
            if im:
                return im
    return None


# the glTF slot of a jnd map name -> the Principled BSDF inputs Blender's
# exporter reads it from (the first linked one gives the image)
SLOT_INPUTS = {
    "baseColor": ("Base Color",),
    "metallicRoughness": ("Roughness", "Metallic"),
    "normal": ("Normal",),
    "emissive": ("Emission",),
}


def _slot_image(material, slot):
    """The Blender image feeding a material's glTF slot, or None."""
    if not material or not material.use_nodes:
        return None
    nodes = material.node_tree.nodes
    if slot == "occlusion":   # the exporter's "glTF Settings"/"glTF Material Output" group
        for n in nodes:
            if n.type == "GROUP" and "Occlusion" in n.inputs:
                return _upstream_image(n.inputs["Occlusion"])
        return None
    for n in nodes:
        if n.type == "BSDF_PRINCIPLED":
            for name in SLOT_INPUTS.get(slot, ()):
                if name in n.inputs:
                    im = _upstream_image(n.inputs[name])
                    if im:
                        return im
    return None


def _map_image(obj, map_name):
    """The name of the Blender image behind one of jnd's maps (MATERIAL/SLOT), or None."""
    material, _, slot = map_name.rpartition("/")
    mats = {m.name: m for m in (s.material for s in obj.material_slots) if m}
    bl = _slot_image(mats.get(material), slot)
    return bl.name if bl else None


def _next_smaller(m):
    """Why a map is not smaller: the first candidate below the chosen size
    judged in its series, its statistic and whether that is a lower bound
    (the search stopped there), or None (nothing smaller was judged)."""
    for size, stat, early in zip(m.get("candidates", []), m.get("series", []), m.get("series_decided_early", [])):
        if size[0] * size[1] < m["chosen"][0] * m["chosen"][1] and stat is not None:
            return {"size": size, "p": stat, "at_least": bool(early)}
    return None


def _length(context, d):
    """A distance in the exported file's units — Blender units, which the
    glTF exporter writes as metres (jnd's reports say _m) — as the scene
    shows lengths (its unit system and scale), or in object units where
    the scene has none."""
    us = context.scene.unit_settings
    if us.system == "NONE":
        return f"{d:.3g} object units"
    return bpy.utils.units.to_string(us.system, "LENGTH", d * us.scale_length, precision=3)


def _summary(obj, result):
    """What the panel shows and Apply needs, from jnd's report: the
    criterion, memory (RGBA8 with mips) and per image the chosen size with
    the Blender image it is."""
    images = []
    for im in result.memory["images"]:
        first = next(m for m in result.maps if m["name"] == im["maps"][0])
        images.append({"maps": im["maps"], "original": im["original"], "chosen": im["chosen"],
                       "image": _map_image(obj, first["name"]), "next": _next_smaller(first)})
    crit = result.views["criterion"]
    return {"p": crit["statistic"], "p_worst": max(result.views["p"]), "threshold": crit["p"], "q": crit["q"],
            "passes": bool(result.passes), "before_mib": result.memory["before_bytes"] / MIB,
            "after_mib": result.memory["after_bytes"] / MIB, "images": images}


class _RunOnObject:
    """An operator that exports the active mesh alone and runs one jnd task
    on it: a subclass names the task and the object's custom property that
    keeps the run's summary, and says the task's options (task_options), what
    the panel keeps of the result (summarise) and the line it reports
    (report_line)."""
    bl_options = {"REGISTER"}
    task = ""
    prop = ""

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == "MESH"

    def task_options(self, s) -> dict:
        """The task's keyword arguments from the panel's settings s."""
        raise NotImplementedError

    def summarise(self, obj, result, out) -> dict:
        """What the panel shows and Apply needs (JSON-able)."""
        raise NotImplementedError

    def report_line(self, summary) -> str:
        raise NotImplementedError

    def package(self, context):
        """The jnd package with only the active object selected (what the
        exporter's use_selection exports), or None after reporting why."""
        try:
            jnd = _jnd()
        except ImportError as e:
            self.report({"ERROR"}, f"jnd: the Python package is not found ({e}); set the add-on's "
                                   "'jnd Python folder' or JND_PYTHONPATH")
            return None
        obj = context.active_object
        for o in context.selected_objects:
            if o is not obj:
                o.select_set(False)
        obj.select_set(True)
        return jnd

    def _export_and_run(self, context, task, **options):
        """Exports the active object alone as GLB into a folder of Blender's
        temporary folder, kept (Apply imports from it), and runs
        jnd.<task>(glb, out_dir, **options) off the main thread, its
        progress lines on the console: (its result, out_dir), or None after
        reporting why not."""
        jnd = self.package(context)
        if jnd is None:
            return None
        folder = tempfile.mkdtemp(prefix=f"jnd_{task}_", dir=bpy.app.tempdir or None)
        glb = os.path.join(folder, f"{bpy.path.clean_name(context.active_object.name)}.glb")
        bpy.ops.export_scene.gltf(filepath=glb, export_format="GLB", use_selection=True)
        out = os.path.join(folder, task)

        def progress(line, done, total):
            if line:   # Blender's progress bar is the main thread's: the console's
                print(f"jnd {task}: {line} ({done}/{total})")

        run = getattr(jnd, task)
        try:
            return _off_main_thread(lambda: run(glb, out, progress=progress, **options)), out
        except jnd.JndError as e:
            self.report({"ERROR"}, f"jnd: {e}")
            return None

    def execute(self, context):
        obj = context.active_object
        ran = self._export_and_run(context, self.task, **self.task_options(context.scene.jnd))
        if ran is None:
            return {"CANCELLED"}
        summary = self.summarise(obj, *ran)
        obj[self.prop] = json.dumps(summary)
        self.report({"INFO"}, self.report_line(summary))
        return {"FINISHED"}


class JND_OT_texres(_RunOnObject, bpy.types.Operator):
    """Exports the selected object as GLB and runs jnd texres on it"""
    bl_idname = "jnd.texres"
    bl_label = "Run texres"
    task, prop = "texres", PROP

    def task_options(self, s):
        return dict(display=s.display, p=_decimal(s.p), q=_decimal(s.q), views=s.views,
                    size=(s.view_size, s.view_size), confirm=s.confirm, min_size=s.min_size)

    def summarise(self, obj, result, out):
        return _summary(obj, result)

    def report_line(self, summary):
        return (f"jnd: P {summary['p']:.3f}, {summary['before_mib']:.2f} MiB -> {summary['after_mib']:.2f} MiB"
                + ("" if summary["passes"] else " (fails)"))


class _ApplyRun:
    """An operator that applies the active object's last run (its custom
    property prop holds the run's summary)."""
    bl_options = {"REGISTER", "UNDO"}
    prop = ""

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and cls.prop in context.active_object


class JND_OT_apply(_ApplyRun, bpy.types.Operator):
    """Scales the object's images to the sizes jnd chose (packed into the .blend)"""
    bl_idname = "jnd.apply"
    bl_label = "Apply"
    prop = PROP

    def execute(self, context):
        n = _scale_images(json.loads(context.active_object[PROP])["images"])
        self.report({"INFO"}, f"jnd: {n} image{'s' if n != 1 else ''} scaled")
        return {"FINISHED"}


def _scale_images(images):
    """Scales each Blender image to the size chosen for it (one image may
    hold several of jnd's maps: the largest wins) and packs the scaled
    pixels into the .blend (the file on disk is untouched); how many were
    scaled."""
    want = {}
    for im in images:
        if im["image"]:
            w, h = want.get(im["image"], (0, 0))
            want[im["image"]] = (max(w, im["chosen"][0]), max(h, im["chosen"][1]))
    n = 0
    for name, (w, h) in want.items():
        image = bpy.data.images.get(name)
        if image is None or tuple(image.size) == (w, h):
            continue
        image.scale(w, h)
        image.pack()
        n += 1
    return n


def _import_gltf(path):
    """Blender's glTF importer; Debian's blender 3.4 importer uses np.bool,
    which Debian 12's numpy (1.24) no longer has: the alias restored for it."""
    import numpy
    if not hasattr(numpy, "bool"):
        numpy.bool = bool
    before = set(bpy.data.objects)
    bpy.ops.import_scene.gltf(filepath=path)
    return [o for o in bpy.data.objects if o not in before]


class JND_OT_lod(_RunOnObject, bpy.types.Operator):
    """Exports the selected object as GLB and runs jnd lod on it for the screen"""
    bl_idname = "jnd.lod"
    bl_label = "Run lod"
    task, prop = "lod", LOD_PROP

    def task_options(self, s):
        return dict(screens=[s.display], p=_decimal(s.p), q=_decimal(s.q), views=s.lod_views, judge_views=s.views,
                    max_px=max(32, s.view_size), errors=s.lod_errors or None)

    def summarise(self, obj, r, out):
        sw = r.screens[0]   # the one screen
        return {"levels": [lv["triangles"] for lv in r.levels], "glb": os.path.join(out, r.model["path"]),
                "screen": sw["name"], "perceptual_level": sw["perceptual_level"],
                "switch_distance": [-1 if d is None else d for d in sw["switch_distance_m"]]}

    def report_line(self, summary):
        k = summary["perceptual_level"]
        return (f"jnd: {len(summary['levels'])} levels; on {summary['screen']} level {k} "
                f"({summary['levels'][k]} of {summary['levels'][0]} triangles)")


class JND_OT_apply_lod(_ApplyRun, bpy.types.Operator):
    """Imports jnd's levels as objects parented to the selected one, in a collection"""
    bl_idname = "jnd.apply_lod"
    bl_label = "Apply LOD"
    prop = LOD_PROP

    def execute(self, context):
        obj = context.active_object
        return _apply_levels(self, context, obj, json.loads(obj[LOD_PROP]), "run lod")


def _apply_levels(op, context, obj, summary, again):
    """Imports the levels of summary["glb"] (jnd names level k's node
    LOD<k>) into the collection "<object> LOD", parented to obj, levels 1..
    hidden, with their triangles and switch distances; op's report says
    what happened."""
    if not os.path.isfile(summary["glb"]):
        op.report({"ERROR"}, f"jnd: {summary['glb']}: gone; {again} again")
        return {"CANCELLED"}
    name = f"{obj.name} LOD"
    old = bpy.data.collections.get(name)
    if old:   # a second Apply replaces the first's levels
        for o in list(old.objects):
            bpy.data.objects.remove(o, do_unlink=True)
    coll = old or bpy.data.collections.new(name)
    if not old:
        context.scene.collection.children.link(coll)
    imported = _import_gltf(summary["glb"])
    # jnd names level k's node LOD<k> (jnd_scene_write_lod_glb)
    levels = {}
    for o in imported:
        if o.type == "MESH" and o.name.startswith("LOD") and o.name[3:].split(".")[0].isdigit():
            levels[int(o.name[3:].split(".")[0])] = o
    if sorted(levels) != list(range(len(summary["levels"]))):
        for o in imported:
            bpy.data.objects.remove(o, do_unlink=True)
        op.report({"ERROR"}, f"jnd: {summary['glb']} does not hold levels 0..{len(summary['levels']) - 1}")
        return {"CANCELLED"}
    for o in imported:
        if o not in levels.values():
            bpy.data.objects.remove(o, do_unlink=True)
    for k, o in sorted(levels.items()):
        for c in list(o.users_collection):
            c.objects.unlink(o)
        coll.objects.link(o)
        o.name = f"{obj.name}_LOD{k}"
        o["jnd_lod_level"] = k
        o["jnd_triangles"] = summary["levels"][k]
        o["jnd_switch_distance"] = summary["switch_distance"][k]
        world = o.matrix_world.copy()
        o.parent = obj
        o.matrix_world = world
        o.hide_set(k > 0)
        o.hide_render = k > 0
    op.report({"INFO"}, f"jnd: {len(levels)} levels in collection {name}")
    return {"FINISHED"}


class JND_OT_budget(_RunOnObject, bpy.types.Operator):
    """Exports the selected object as GLB and runs jnd budget on it: texture sizes and levels chosen together"""
    bl_idname = "jnd.budget"
    bl_label = "Run budget"
    task, prop = "budget", BUDGET_PROP

    def task_options(self, s):
        return dict(display=s.display, screens=[s.display], p=_decimal(s.p), q=_decimal(s.q), views=s.views,
                    size=(s.view_size, s.view_size), confirm=s.confirm, min_size=s.min_size, judge_views=s.views,
                    max_px=max(32, s.view_size), errors=s.lod_errors or None,
                    memory=f"{_decimal(s.budget_memory)}MiB" if s.budget_memory > 0 else None,
                    triangles=s.budget_triangles or None)

    def summarise(self, obj, result, out):
        return _budget_summary(obj, result, out)

    def report_line(self, summary):
        c = summary["chosen"]
        return (f"jnd: level {c['level']}, {c['triangles']} triangles, {c['memory_mib']:.2f} MiB "
                f"of textures, P {c['statistic']:.3f}" + ("" if summary["passes"] else " (fails)"))


def _budget_summary(obj, result, out):
    """What the panel shows and Apply budget needs, from jnd budget's report:
    the chosen candidate (its finest level, triangles, texture memory,
    statistic), the texres-then-lod choice it is compared with, per map the
    chosen size with the Blender image it is, and the written levels."""
    def candidate(c):
        return {"level": c["level"], "triangles": c["triangles"], "memory_mib": c["memory_bytes"] / MIB,
                "cost_mib": c["cost_bytes"] / MIB, "statistic": c["statistic"], "pass": bool(c["pass"])}
    images = []
    for name, size in result.chosen["sizes"].items():
        image = _map_image(obj, name)
        original = list(bpy.data.images[image].size) if image else None
        images.append({"maps": [name], "original": original, "chosen": size, "image": image})
    return {"chosen": candidate(result.chosen), "separate": candidate(result.separate),
            "passes": bool(result.passes), "threshold": result.report["parameters"]["criterion"]["p"],
            "images": images, "levels": [lv["triangles"] for lv in result.levels],
            "switch_distance": [-1 if lv["switch_distance"] is None else lv["switch_distance"]
                                for lv in result.levels],
            "glb": os.path.join(out, result.model)}


class JND_OT_apply_budget(_ApplyRun, bpy.types.Operator):
    """Scales the object's images to jnd budget's sizes and imports its levels as objects parented to it"""
    bl_idname = "jnd.apply_budget"
    bl_label = "Apply budget"
    prop = BUDGET_PROP

    def execute(self, context):
        obj = context.active_object
        summary = json.loads(obj[BUDGET_PROP])
        n = _scale_images(summary["images"])
        done = _apply_levels(self, context, obj, summary, "run budget")
        if done == {"FINISHED"}:
            self.report({"INFO"}, f"jnd: {n} image{'s' if n != 1 else ''} scaled, "
                                  f"{len(summary['levels'])} levels in collection {obj.name} LOD")
        return done


class JND_PT_panel(bpy.types.Panel):
    bl_label = "jnd"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "jnd"

    def draw(self, context):
        lay, s, obj = self.layout, context.scene.jnd, context.active_object
        self.draw_texres(lay, s, obj)
        lay.separator()
        self.draw_lod(context, lay, s, obj)
        lay.separator()
        self.draw_budget(context, lay, s, obj)

    @staticmethod
    def draw_texres(lay, s, obj):
        col = lay.column()
        col.prop(s, "display")
        row = col.row(align=True)
        row.prop(s, "p")
        row.prop(s, "q")
        col.prop(s, "views")
        col.prop(s, "view_size")
        col.prop(s, "confirm")
        col.prop(s, "min_size")
        col.operator(JND_OT_texres.bl_idname, icon="TEXTURE")
        if obj is None or PROP not in obj:
            return
        r = json.loads(obj[PROP])
        box = lay.box()
        # short lines: the sidebar is narrow
        box.label(text=f"P {r['p']:.3f}, worst view {r['p_worst']:.3f}")
        box.label(text=f"P <= {r['threshold']:g}, Q {r['q']:g}: " + ("passes" if r["passes"] else "FAILS"))
        box.label(text=f"{r['before_mib']:.2f} -> {r['after_mib']:.2f} MiB")   # RGBA8 with mips
        for im in r["images"]:   # the name, then the sizes: one line is cut in the sidebar
            box.label(text=f"{im['image'] or ', '.join(im['maps'])}:")
            box.label(text=f"  {im['original'][0]}x{im['original'][1]} -> {im['chosen'][0]}x{im['chosen'][1]}")
            nxt = im.get("next")
            if nxt:   # why it is not smaller
                box.label(text=f"  {nxt['size'][0]}x{nxt['size'][1]}: P {'>= ' if nxt['at_least'] else ''}"
                               f"{nxt['p']:.3f}")
        box.operator(JND_OT_apply.bl_idname, icon="CHECKMARK")

    @staticmethod
    def draw_levels(context, box, levels, distances):
        box.label(text="level: triangles, from distance")
        for i, (t, d) in enumerate(zip(levels, distances)):
            box.label(text=f"{i}: {t}, " + ("never" if d < 0 else _length(context, d)))

    @staticmethod
    def draw_budget(context, lay, s, obj):
        col = lay.column()
        col.prop(s, "budget_memory")   # a line each: side by side the sidebar cuts their names
        col.prop(s, "budget_triangles")
        col.operator(JND_OT_budget.bl_idname, icon="SETTINGS")
        if obj is None or BUDGET_PROP not in obj:
            return
        r = json.loads(obj[BUDGET_PROP])
        box = lay.box()
        c, sep = r["chosen"], r["separate"]
        box.label(text=f"level {c['level']}, {c['triangles']} triangles")
        box.label(text=f"{c['memory_mib']:.2f} MiB textures, P {c['statistic']:.3f}")
        box.label(text=f"P <= {r['threshold']:g}: " + ("passes" if r["passes"] else "FAILS"))
        box.label(text=f"cost {c['cost_mib']:.2f} MiB (apart: {sep['cost_mib']:.2f})")
        for im in r["images"]:
            size = f"{im['original'][0]}x{im['original'][1]} -> " if im["original"] else ""
            box.label(text=f"{im['image'] or ', '.join(im['maps'])}:")
            box.label(text=f"  {size}{im['chosen'][0]}x{im['chosen'][1]}")
        JND_PT_panel.draw_levels(context, box, r["levels"], r["switch_distance"])
        box.operator(JND_OT_apply_budget.bl_idname, icon="CHECKMARK")

    @staticmethod
    def draw_lod(context, lay, s, obj):
        col = lay.column()
        col.prop(s, "lod_errors")
        col.prop(s, "lod_views")
        col.operator(JND_OT_lod.bl_idname, icon="MOD_DECIM")
        if obj is None or LOD_PROP not in obj:
            return
        r = json.loads(obj[LOD_PROP])
        box = lay.box()
        k = r["perceptual_level"]
        box.label(text=f"{r['screen']}: level {k}")
        box.label(text=f"{r['levels'][k]} of {r['levels'][0]} triangles")
        JND_PT_panel.draw_levels(context, box, r["levels"], r["switch_distance"])
        box.operator(JND_OT_apply_lod.bl_idname, icon="CHECKMARK")


CLASSES = (JndPreferences, JndSettings, JND_OT_texres, JND_OT_apply, JND_OT_lod, JND_OT_apply_lod, JND_OT_budget,
           JND_OT_apply_budget, JND_PT_panel)


def register():
    for c in CLASSES:
        bpy.utils.register_class(c)
    bpy.types.Scene.jnd = PointerProperty(type=JndSettings)


def unregister():
    del bpy.types.Scene.jnd
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)


if __name__ == "__main__":
    register()
