"""Takes the screenshot of the add-on's panel in docs/ (README, "Python"),
in two runs: the operators run headless (as in tests/e2e/blender_addon.sh)
and the window only draws their results, which the objects keep:

    JND_PYTHONPATH=build/python blender -b --factory-startup -noaudio \\
        --python blender/tests/panel_screenshot.py -- prepare DIR/panel.blend
    JND_PYTHONPATH=build/python xvfb-run -a -s "-screen 0 1280x1440x24" blender DIR/panel.blend \\
        -noaudio --enable-event-simulate --python blender/tests/panel_screenshot.py -- shoot docs/blender_panel.png

prepare: a UV sphere with a 256² image, the add-on installed and enabled,
Run texres, Run lod and Run budget with small settings, saved (the three
boxes of results showing). shoot: Blender with a
window (Xvfb, Mesa's llvmpipe for GL), the sidebar open on the jnd tab,
bpy.ops.screen.screenshot once the window has been drawn, and quit.
xvfb-run comes from Debian's xvfb (scripts/install-deps.sh).
"""
import os
import sys
import traceback

import bpy

mode, out = sys.argv[sys.argv.index("--") + 1:][:2]
out = os.path.abspath(out)
here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
from scene import textured  # noqa: E402

if mode == "prepare":
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1)
    sphere = bpy.context.active_object
    sphere.name = "Sphere"
    image = textured(sphere, "jnd_grid", "grid")
    bpy.ops.preferences.addon_install(filepath=os.path.join(os.path.dirname(here), "jnd_blender.py"))
    bpy.ops.preferences.addon_enable(module="jnd_blender")
    bpy.ops.wm.save_userpref()
    s = bpy.context.scene.jnd
    s.views, s.view_size, s.confirm = 2, 96, 0
    s.lod_errors, s.lod_views = "1/256,1/64,1/16", 1
    assert bpy.ops.jnd.texres() == {"FINISHED"}
    assert bpy.ops.jnd.lod() == {"FINISHED"}
    assert bpy.ops.jnd.budget() == {"FINISHED"}
    image.pack()
    bpy.ops.wm.save_as_mainfile(filepath=out)
elif mode == "shoot":
    # Blender 3.4 has no Python for the sidebar's active tab: a click on the
    # jnd tab is simulated (blender --enable-event-simulate)
    def tab_position():
        for area in bpy.context.screen.areas:
            if area.type == "VIEW_3D":
                ui = next(r for r in area.regions if r.type == "UI")
                return area, ui
        raise RuntimeError("no 3D viewport")

    def click(x, y):
        win = bpy.context.window
        win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
        win.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
        win.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)

    def crop(path, x0, y0, x1, y1):
        """path cropped to the window rectangle [x0, x1) × [y0, y1) (from the
        bottom left): the viewport's right part with the sidebar"""
        import numpy
        im = bpy.data.images.load(path)
        w, h = im.size
        px = numpy.array(im.pixels[:], dtype=numpy.float32).reshape(h, w, 4)
        x0, y0 = max(0, x0), max(0, y0)
        part = px[y0:min(h, y1), x0:min(w, x1)]
        bpy.data.images.remove(im)
        new = bpy.data.images.new("crop", part.shape[1], part.shape[0])
        new.pixels[:] = part.ravel()
        new.filepath_raw, new.file_format = path, "PNG"
        new.save()

    def step(k=[0]):
        try:
            area, ui = tab_position()
            if k[0] == 0:
                area.spaces.active.show_region_ui = True
                area.spaces.active.shading.type = "MATERIAL"
                with bpy.context.temp_override(area=area, region=next(r for r in area.regions
                                                                       if r.type == "WINDOW")):
                    bpy.ops.view3d.view_selected()
            elif k[0] == 1:
                # the tabs are a strip on the region's right edge, "Item" first
                # Tool, View, then "jnd" (about 20 px wide, each tab about 45 px tall)
                click(ui.x + ui.width - 10, ui.y + ui.height - 160)
            elif k[0] == 3:
                bpy.ops.screen.screenshot(filepath=out)
                crop(out, ui.x + ui.width - 900, area.y, ui.x + ui.width, area.y + area.height)
                print("wrote", out)
                bpy.ops.wm.quit_blender()
                return None
            k[0] += 1
            return 1.5
        except Exception:
            traceback.print_exc()
            bpy.ops.wm.quit_blender()
            return None

    bpy.app.timers.register(step, first_interval=2.0)
