"""Blender's side of tests/e2e/blender_addon.sh, run headless:

    blender -b --factory-startup -noaudio --python-exit-code 1 --python addon_test.py -- run DIR
        builds a plane with a 256x256 generated image on its material, exports
        it as DIR/plane.glb (the exporter's options the add-on uses), installs
        and enables the add-on (blender/jnd_blender.py), runs its operator
        with small settings, applies, saves DIR/scene.blend and writes the
        panel's summary to DIR/summary.json; then the same for LOD on a UV
        sphere (exported as DIR/sphere.glb): Run lod, Apply LOD, the summary
        in DIR/lod_summary.json; then budget on a UV sphere with a 256x256
        image (DIR/ball.glb): Run budget, Apply budget, the summary in
        DIR/budget_summary.json, and the panel's distance in two unit
        systems in DIR/units.json
    blender -b DIR/scene.blend --python-exit-code 1 --python addon_test.py -- check DIR
        writes DIR/sizes.json: each image's name, size and whether it is
        packed, and DIR/levels.json (DIR/ball_levels.json): each object of the
        "Sphere LOD" ("Ball LOD") collection with its level, triangles, parent
        and switch distance
"""
import json
import os
import sys

import bpy

mode, out = sys.argv[sys.argv.index("--") + 1:][:2]
here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
from scene import textured  # noqa: E402

if mode == "run":
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    bpy.ops.mesh.primitive_plane_add(size=2)
    plane = bpy.context.active_object
    textured(plane, "jnd_grid", "grid")
    plane.select_set(True)
    bpy.context.view_layer.objects.active = plane
    # the same export the operator makes, for the command line to judge
    bpy.ops.export_scene.gltf(filepath=os.path.join(out, "plane.glb"), export_format="GLB", use_selection=True)

    bpy.ops.preferences.addon_install(filepath=os.path.join(os.path.dirname(here), "jnd_blender.py"))
    bpy.ops.preferences.addon_enable(module="jnd_blender")
    assert hasattr(bpy.types, "JND_PT_panel"), "the panel is registered"
    s = bpy.context.scene.jnd
    s.display = os.environ.get("JND_TEST_DISPLAY", "standard-fhd")
    s.views, s.view_size, s.confirm = 2, 96, 0
    assert bpy.ops.jnd.texres() == {"FINISHED"}
    summary = json.loads(plane["jnd_texres"])
    assert bpy.ops.jnd.apply() == {"FINISHED"}
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary, f)
    # LOD: a sphere of 960 triangles, its chain judged on the same screen
    plane.select_set(False)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1, location=(3, 0, 0))
    sphere = bpy.context.active_object
    sphere.name = "Sphere"
    bpy.ops.export_scene.gltf(filepath=os.path.join(out, "sphere.glb"), export_format="GLB", use_selection=True)
    s.lod_errors, s.lod_views = "1/256,1/64,1/16", 1
    assert bpy.ops.jnd.lod() == {"FINISHED"}
    lod_summary = json.loads(sphere["jnd_lod"])
    assert bpy.ops.jnd.apply_lod() == {"FINISHED"}
    with open(os.path.join(out, "lod_summary.json"), "w") as f:
        json.dump(lod_summary, f)
    # budget: a textured ball, its texture sizes and levels chosen together
    sphere.select_set(False)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1, location=(6, 0, 0))
    ball = bpy.context.active_object
    ball.name = "Ball"
    textured(ball, "jnd_ball", "ball")
    bpy.ops.export_scene.gltf(filepath=os.path.join(out, "ball.glb"), export_format="GLB", use_selection=True)
    s.lod_errors = "1/64,1/16"   # three levels, not lod's four: fewer candidates (the command: 29 s -> 18 s)
    assert bpy.ops.jnd.budget() == {"FINISHED"}
    budget_summary = json.loads(ball["jnd_budget"])
    assert bpy.ops.jnd.apply_budget() == {"FINISHED"}
    with open(os.path.join(out, "budget_summary.json"), "w") as f:
        json.dump(budget_summary, f)
    # the panel's distances carry their unit: the scene's, or object units where it has none
    import jnd_blender
    units = {"metric": jnd_blender._length(bpy.context, 2.5)}
    bpy.context.scene.unit_settings.system = "NONE"
    units["none"] = jnd_blender._length(bpy.context, 2.5)
    bpy.context.scene.unit_settings.system = "METRIC"
    with open(os.path.join(out, "units.json"), "w") as f:
        json.dump(units, f)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "scene.blend"))
elif mode == "check":
    sizes = {im.name: {"size": list(im.size), "packed": im.packed_file is not None} for im in bpy.data.images}
    with open(os.path.join(out, "sizes.json"), "w") as f:
        json.dump(sizes, f)
    for obj, name in (("Sphere", "levels.json"), ("Ball", "ball_levels.json")):
        coll = bpy.data.collections.get(f"{obj} LOD")
        levels = [{"name": o.name, "level": o.get("jnd_lod_level"),
                   "triangles": sum(len(p.vertices) - 2 for p in o.data.polygons),
                   "parent": o.parent.name if o.parent else None, "switch_distance": o.get("jnd_switch_distance"),
                   "hidden": o.hide_render} for o in (coll.objects if coll else [])]
        with open(os.path.join(out, name), "w") as f:
            json.dump(sorted(levels, key=lambda x: x["level"]), f)
else:
    sys.exit(f"addon_test.py: unknown mode {mode}")
