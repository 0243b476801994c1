"""The Python package gives the command's numbers, round-trips arrays, and
turns every bad input into a JndError with libjnd's message."""
import json
import math
import os
import resource
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import jnd

JND = os.environ["JND"]          # the command-line tool of the same build
# the command runs without the interpreter's preloaded sanitizer runtime (the
# sanitizer build's jnd carries its own)
CLI_ENV = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
SANITIZED = bool(os.environ.get("JND_SANITIZED"))


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    d = tmp_path_factory.mktemp("demo")
    subprocess.run([JND, "example", "-o", str(d)], check=True, capture_output=True, env=CLI_ENV)
    return str(d / "reference.png"), str(d / "test.png")


def cli_diff(ref, test, *args):
    out = subprocess.run([JND, "diff", ref, test, "--json", "-", *args], capture_output=True, text=True, env=CLI_ENV)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)["result"]


def test_diff_of_files_gives_the_commands_figures(demo):
    for disp in ("standard-fhd", "phone"):
        want = cli_diff(*demo, "--display", disp)
        got = jnd.diff(*demo, display=disp)
        # cJSON prints 15 significant digits when they read back within its
        # epsilon of the value, so the JSON is the value to about 1e-15
        for k in ("p_detect", "p_p50", "p_p93", "p_p99", "p_max", "p_mean", "jnd_mean", "jnd_p93", "jnd_max",
                  "jnd_minkowski"):
            assert getattr(got, k) == pytest.approx(want[k], rel=1e-14, abs=1e-300), k
        for k in ("width", "height", "bands_cpd"):
            assert getattr(got, k) == want[k], k


def test_diff_of_arrays_equals_the_diff_of_their_files(demo):
    a, enc = jnd.read_image(demo[0])
    b, _ = jnd.read_image(demo[1])
    assert enc == "srgb" and a.dtype == np.float32 and a.ndim == 3
    from_files = jnd.diff(*demo)
    from_arrays = jnd.diff(a, b)
    assert from_arrays.p_detect == from_files.p_detect
    assert np.array_equal(from_arrays.jnd_map, from_files.jnd_map)
    # uint8 arrays are scaled by 255, as an 8-bit PNG is
    a8 = np.round(a * 255).astype(np.uint8)
    b8 = np.round(b * 255).astype(np.uint8)
    assert jnd.diff(a8, b8).p_detect == from_files.p_detect


def test_the_jnd_map_is_written_per_pixel_where_the_images_differ():
    ref = np.full((64, 256, 3), 0.5, np.float32)
    test = ref.copy()
    test[20:40, 200:220] += 0.1
    r = jnd.diff(ref, test)
    assert r.jnd_map.shape == (64, 256) and r.jnd_map.dtype == np.float32
    y, x = np.unravel_index(np.argmax(r.jnd_map), r.jnd_map.shape)
    assert 15 <= y < 45 and 195 <= x < 225          # the peak is at the patch (row, column order)
    inside = r.jnd_map[25:35, 205:215].mean()
    far = r.jnd_map[:, :40].max()                   # 4 degrees away on standard-fhd
    assert inside > 1 and far < 0.2 * inside
    assert r.width == 256 and r.height == 64


def test_identical_images_are_not_noticed():
    a = np.random.default_rng(1).random((48, 48, 3), dtype=np.float32)
    r = jnd.diff(a, a.copy())
    assert r.p_detect == 0 and r.jnd_max == 0


def test_a_larger_change_is_more_visible():
    ref = np.full((64, 64), 0.4, np.float32)
    ps = [jnd.diff(ref, ref + d).jnd_max for d in (0.002, 0.01, 0.05)]
    assert ps[0] < ps[1] < ps[2]


def test_linear_arrays_go_through_the_displays_exr_scale():
    ref = np.full((64, 64, 3), 50.0, np.float32)
    test = ref.copy()
    test[16:48, 16:48] *= 1.05
    d1 = jnd.display("standard-fhd", exr_scale=1.0)
    r1 = jnd.diff(ref, test, display=d1, encoding="linear")
    r2 = jnd.diff(ref / 2, test / 2, display=jnd.display("standard-fhd", exr_scale=2.0), encoding="linear")
    assert r1.jnd_max == pytest.approx(r2.jnd_max, rel=1e-5)


def test_display_presets_and_ppd():
    names = jnd.display_presets()
    assert "standard-fhd" in names and "standard-4k" in names
    for name in names:
        d = jnd.display(name)
        if d.diagonal_in > 0:
            assert d.ppd == pytest.approx(jnd.ppd_from_geometry(d.diagonal_in, d.width_px, d.height_px,
                                                                d.distance_m), rel=1e-12), name
    # the model's finest band peaks at a fixed fraction of the display's ppd
    fhd, uhd = jnd.Model("standard-fhd"), jnd.Model("standard-4k")
    ratio = uhd.display.ppd / fhd.display.ppd
    assert uhd.bands_cpd()[0] == pytest.approx(ratio * fhd.bands_cpd()[0], rel=1e-3)


def test_gaze_makes_the_periphery_less_visible():
    ref = np.full((96, 384, 3), 0.5, np.float32)
    test = ref.copy()
    test[40:56, 300:316] += 0.05
    fovea = jnd.diff(ref, test, gaze=(308, 48)).jnd_max
    periphery = jnd.diff(ref, test, gaze=(8, 48)).jnd_max
    assert periphery < fovea


def test_probability_is_000_eq_4():
    assert jnd.probability(1.0) == pytest.approx(0.5)
    assert jnd.probability(2.0, 3.5) == pytest.approx(1 - np.exp(np.log(0.5) * 2 ** 3.5))


@pytest.mark.parametrize("bad,needle", [
    (np.zeros((8, 8, 5), np.float32), "C = 1..4"),
    (np.zeros((8,), np.float32), "shape"),
    (np.zeros((8, 8), np.int32), "dtype"),
    (np.full((8, 8), np.nan, np.float32), "NaN"),
    (np.full((8, 8), -1, np.float32), "negative"),
    ([[0.5]], "NumPy array"),
])
def test_bad_arrays_raise_with_a_message(bad, needle):
    with pytest.raises(jnd.JndError, match=needle):
        jnd.diff(bad, np.zeros((8, 8), np.float32))


def test_library_errors_carry_jnds_message(tmp_path):
    missing = str(tmp_path / "missing.png")
    with pytest.raises(jnd.JndError) as e:
        jnd.diff(missing, missing)
    assert str(e.value).startswith(missing) and e.value.status == "JND_ERR_IO"
    with pytest.raises(jnd.JndError, match="sizes differ"):
        jnd.diff(np.zeros((8, 8), np.float32), np.zeros((8, 9), np.float32))
    with pytest.raises(jnd.JndError, match="standard-fhd"):   # the message lists the presets
        jnd.display("cinema")
    with pytest.raises(jnd.JndError):
        jnd.diff(np.zeros((8, 8), np.float32), np.zeros((8, 8), np.float32), pooling="p200")
    with pytest.raises(jnd.JndError, match="encoding"):
        jnd.diff(np.zeros((8, 8), np.float32), np.zeros((8, 8), np.float32), encoding="gamma")


@pytest.mark.skipif(SANITIZED, reason="ASan's quarantine keeps freed memory resident; its leak check covers the C suite")
def test_repeated_calls_do_not_leak():
    m = jnd.Model()
    ref = np.random.default_rng(2).random((128, 128, 3), dtype=np.float32)
    test = np.clip(ref + 0.01, 0, 1)

    def rss_kib():
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * resource.getpagesize() // 1024

    for _ in range(20):
        m.diff(ref, test)
    before = rss_kib()
    for _ in range(200):
        m.diff(ref, test)
        try:
            m.diff("/nonexistent.png", test)
        except jnd.JndError:
            pass
    grown = rss_kib() - before
    # each call allocates about 0.4 MiB of images and maps: 200 leaked calls would be 80 MiB
    assert grown < 8 * 1024, f"resident memory grew by {grown} KiB over 200 calls"


def ticks_during(call):
    """How long call() took, and how many times another Python thread ran
    (about once a millisecond while the GIL is free) meanwhile."""
    ticks, done = [], threading.Event()

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.01)
    t0 = time.perf_counter()
    call()
    t1 = time.perf_counter()
    done.set()
    t.join()
    return t1 - t0, len([x for x in ticks if t0 < x < t1])


def test_the_gil_is_released_during_a_comparison():
    ref = np.random.default_rng(3).random((1024, 1024, 3), dtype=np.float32)
    test = np.clip(ref + 0.02, 0, 1)
    m = jnd.Model(threads=1)
    seconds, during = ticks_during(lambda: m.diff(ref, test))
    # a held GIL would let the other thread tick at most once or twice during the call
    assert seconds < 0.05 or during >= 5, (seconds, during)


def test_one_model_serves_several_threads():
    m = jnd.Model()
    ref = np.full((64, 64, 3), 0.5, np.float32)
    test = ref.copy()
    test[10:30, 10:30] += 0.03
    want = m.diff(ref, test).jnd_max
    got = []
    ts = [threading.Thread(target=lambda: got.append(m.diff(ref, test).jnd_max)) for _ in range(4)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert got == [want] * 4


# ------------------------------------------------------------- task runs --
# Each task from Python gives the command's report, byte for byte, with the
# same options (the report names the output folder, so both write to the
# same path, one after the other).

SMALL = ["--views", "2", "--size", "96x96", "--map-size", "128", "--samples", "1"]
SMALL_KW = dict(views=2, size="96x96", map_size=128, samples=1)
TINY = ["--views", "1", "--size", "64x64", "--map-size", "64", "--samples", "1"]   # the slower tasks
TINY_KW = dict(views=1, size=(64, 64), map_size=64, samples=1)


@pytest.fixture(scope="module")
def renderer(tmp_path_factory):
    d = tmp_path_factory.mktemp("probe")
    out = subprocess.run([JND, "render", "builtin", "-o", str(d / "r"), "--views", "1", "--size", "16x16",
                          "--map-size", "16", "--quiet"], capture_output=True, text=True, env=CLI_ENV)
    if out.returncode != 0:
        if "OpenGL" in out.stderr or "EGL" in out.stderr:
            pytest.skip("no OpenGL renderer: " + out.stderr.strip())
        pytest.fail("the renderer probe failed: " + out.stderr)


def cli_task(task, args, out, report):
    """The command's report text (--json FILE) and its folder's files."""
    cmd = [JND, *task.split(), *args, "-o", str(out), "--json", str(report), "--quiet"]
    run = subprocess.run(cmd, capture_output=True, text=True, env=CLI_ENV)
    assert run.returncode in (0, 1), run.stderr
    return report.read_text()


def files_of(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def same_as_cli(tmp_path, task, cli_args, call, report_name=None):
    out = tmp_path / "out"
    want = cli_task(task, cli_args, out, tmp_path / "cli.json")
    want_files = files_of(out) if out.is_dir() else None
    want_file = out.read_text() if out.is_file() else None
    out.rename(tmp_path / "cli")
    got = call(out)
    assert got.report_text == want
    if want_files is not None:
        assert files_of(out) == want_files
        name = report_name or f"{task.split()[0]}.json"
        assert (out / name).read_text() == (tmp_path / "cli" / name).read_text()
    if want_file is not None:
        assert out.read_text() == want_file
    return got


def test_texres_from_python_is_the_commands_report(tmp_path, renderer):
    args = ["builtin", *SMALL, "--confirm", "0", "--min-size", "16", "--p", "0.3", "--display", "phone"]
    lines = []
    r = same_as_cli(tmp_path, "texres", args,
                    lambda out: jnd.texres("builtin", out, confirm=0, min_size=16, p=0.3, display="phone",
                                           progress=lambda *a: lines.append(a), **SMALL_KW))
    assert r.passes is True and r.report["command"] == "texres"
    assert r.maps and all(m["chosen"][0] <= m["original"][0] for m in r.maps)
    assert r.memory["after_bytes"] <= r.memory["before_bytes"]
    # the callback: after each rendering (line None) and a summary per stage
    assert any(line is None for line, _, _ in lines) and any(line for line, _, _ in lines)
    assert all(isinstance(d, int) and isinstance(t, int) for _, d, t in lines)


def test_texres_options_reach_the_library_with_the_gil_free(tmp_path, renderer):
    args = ["builtin", *SMALL, "--confirm", "0", "--sizes", "128,64", "--maps", "baseColor", "--ppd", "60",
            "--peak", "400", "--elevation", "10,40", "--q", "0.5"]
    timing = []

    def call(out):
        result = []
        timing.append(ticks_during(lambda: result.append(
            jnd.texres("builtin", out, confirm=0, sizes=[128, 64], maps=["baseColor"], ppd=60, peak=400,
                       elevation=(10, 40), q=0.5, **SMALL_KW))))
        return result[0]

    same_as_cli(tmp_path, "texres", args, call)
    # no progress callback: a GIL held for the whole run (seconds) would let
    # the other thread tick once or twice
    seconds, during = timing[0]
    assert during >= 50, (seconds, during)


def test_pca_from_python_is_the_commands_report(tmp_path, renderer):
    args = ["--model", "builtin", "--material", "builtin", *TINY, "--anisotropy", "1", "--no-bc"]
    r = same_as_cli(tmp_path, "pca", args,
                    lambda out: jnd.pca([], out, model="builtin", material="builtin", anisotropy=1, no_bc=True,
                                        **TINY_KW))
    assert r.passes is None and r.report["command"] == "pca"


def shared_maps(folder):
    """Two of the shared helmet's maps (2048² JPEG), every eighth pixel of
    them as 256² PNG files in folder: the same content at a 64th of the
    pixels (the command and the package read the same files)."""
    d = os.path.join(os.environ.get("JND_SHARED", "/nonexistent"), "data/texsets/damagedhelmet")
    maps = [os.path.join(d, f) for f in ("Default_AO.jpg", "Default_albedo.jpg")]
    if not all(os.path.isfile(m) for m in maps):
        pytest.skip("needs the shared texture sets ($JND_SHARED/data/texsets)")
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "e2e"))
    from pngwrite import png
    small = []
    for m in maps:
        a, _ = jnd.read_image(m)
        h, w, c = a[::8, ::8].shape
        rows = a[::8, ::8].tolist()   # Python floats: pngwrite's loop is per pixel
        path = os.path.join(folder, os.path.basename(m)[:-4] + ".png")
        png(path, w, h, c, lambda x, y: rows[y][x])
        small.append(path)
    return small


def test_pca_of_map_files_is_the_commands_report(tmp_path):
    maps = shared_maps(tmp_path)
    args = [*maps, "--components", "3", "--bits", "16,8", "--resolutions", "1,2", "--weight", "albedo=2"]
    same_as_cli(tmp_path, "pca", args,
                lambda out: jnd.pca(maps, out, components=3, bits=[16, 8], resolutions="1,2", weight="albedo=2"))
    # the command's checks of the options, with its messages
    with pytest.raises(jnd.JndError, match="--bits and --resolutions go with --components"):
        jnd.pca(maps, tmp_path / "x", psnr=40, resolutions=[1, 2])
    with pytest.raises(jnd.JndError, match="--resolutions: 3 is not a power of two"):
        jnd.pca(maps, tmp_path / "x", components=2, resolutions=[1, 3])
    assert not (tmp_path / "x").exists()


def test_calibrate_from_python_is_the_commands_file(tmp_path, renderer):
    csv = tmp_path / "rates.csv"
    csv.write_text("scene,model,map,resolution,rate\n"
                   "albedo,builtin,builtin/baseColor,64,0.0\nalbedo,builtin,builtin/baseColor,32,0.5\n"
                   "albedo,builtin,builtin/baseColor,16,0.95\nnormal,builtin,builtin/normal,64,0.0\n"
                   "normal,builtin,builtin/normal,32,0.8\nnormal,builtin,builtin/normal,16,1.0\n")
    args = [str(csv), "--folds", "2", "--p", "0.25", *TINY]
    r = same_as_cli(tmp_path, "calibrate", args, lambda out: jnd.calibrate(csv, out, folds=2, p=0.25, **TINY_KW))
    assert r.report["command"] == "calibrate"


def test_bad_task_input_raises_jnds_message_and_writes_nothing(tmp_path):
    out = tmp_path / "out"
    missing = tmp_path / "nope.glb"
    with pytest.raises(jnd.JndError) as e:
        jnd.texres(missing, out, views=2)
    want = subprocess.run([JND, "texres", str(missing), "-o", str(out), "--views", "2"], capture_output=True,
                          text=True, env=CLI_ENV)
    assert want.returncode == 2 and want.stderr.strip() == "jnd: " + str(e.value)
    assert str(missing) in str(e.value)
    assert not out.exists()
    bad = tmp_path / "bad.gltf"
    bad.write_text("{ not json")
    with pytest.raises(jnd.JndError, match="bad.gltf"):
        jnd.texres(bad, out)
    assert not out.exists()
    with pytest.raises(jnd.JndError, match="bad.csv"):
        jnd.calibrate(tmp_path / "bad.csv", tmp_path / "cal.json")
    assert not (tmp_path / "cal.json").exists()


# The library checks most fields and says what is wrong in one line; the
# package converts keywords (a number, an integer, WxH, a list) with the
# command's messages and checks only the ranges the library takes as they
# come (the sizes, the renderer's samples, the display's ambient ...).
@pytest.mark.parametrize("kw,needle", [
    (dict(views=0), "views: no views (0)"),                                  # the library's
    (dict(fov=500), "views: field of view 500 is outside (0, 180)"),
    (dict(margin=2), "texres: margin 2 is outside [0, 1)"),
    (dict(p=2), "texres: criterion p 2, q 0.1"),
    (dict(ppd=0.5), "pixels per degree must be in [1, 1000], not 0.5"),
    (dict(platform="x11"), "EGL platform 'x11' is not auto, device or surfaceless"),
    (dict(display="no-such-screen"), "no-such-screen"),
    (dict(views="2.5"), "--views: '2.5' is not an integer"),                  # the conversions
    (dict(margin="half"), "--margin: 'half' is not a number"),
    (dict(size="96"), "--size: '96' is not WxH"),
    (dict(size="8x8"), "--size: '8x8' is not WxH with W and H in 16..16384"),  # not the library's
    (dict(pool="max"), "--pool: 'max' is not a percentile"),
    (dict(sizes="64,abc"), "--sizes:"),
])
def test_bad_options_raise_one_line_and_write_nothing(tmp_path, kw, needle):
    with pytest.raises(jnd.JndError) as e:   # the builtin asset's smallest maps: the check, not the asset, is tested
        jnd.texres("builtin", tmp_path / "out", map_size=16, **kw)
    assert needle in str(e.value) and "\n" not in str(e.value)
    assert not (tmp_path / "out").exists()


def test_the_package_does_not_repeat_the_librarys_checks():
    """A range the library checks is not checked again in Python: the
    source names no range for those options (python/jnd/tasks.py)."""
    import inspect
    from jnd import tasks
    src = inspect.getsource(tasks)
    for opt in ("views", "coverage", "fov", "lights", "map_size", "margin", "confirm", "verify_views",
                "min_size", "energy", "components", "tolerance", "far_coverage", "max_px", "judge_views",
                "virtual_scale", "surface_samples", "orientations", "threshold", "confidence", "answers",
                "min_px", "triangles", "bytes_per_triangle"):
        for line in src.splitlines():
            if f'"{opt}"' in line and "number(" in line:
                assert "integer=True)" in line or f'number("{opt}")' in line, line


def test_unknown_keywords_are_a_type_error(tmp_path):
    with pytest.raises(TypeError, match="no_such_option"):
        jnd.texres("builtin", tmp_path / "out", no_such_option=1)


def test_an_exception_in_the_progress_callback_surfaces(tmp_path, renderer):
    calls = []

    def progress(line, done, total):
        calls.append(done)
        raise ValueError("from the callback")

    with pytest.raises(ValueError, match="from the callback"):
        jnd.texres("builtin", tmp_path / "out", confirm=0, progress=progress, **TINY_KW)
    assert len(calls) == 1   # not called again after it raised


def test_lod_from_python_is_the_commands_report(tmp_path, renderer):
    args = ["builtin", "--map-size", "64", "--screens", "phone,320x240@20", "--judge-views", "1", "--views", "1",
            "--max-px", "64", "--errors", "1/256,1/64", "--no-textures", "--pop-motion", "spin"]
    stages = []
    r = same_as_cli(tmp_path, "lod", args,
                    lambda out: jnd.lod("builtin", out, map_size=64, screens=["phone", "320x240@20"], judge_views=1,
                                        views=1, max_px=64, errors="1/256,1/64", no_textures=True,
                                        pop_motion="spin", progress=lambda *a: stages.append(a[0])))
    assert r.report["command"] == "lod" and len(r.levels) == 3
    assert stages and all(isinstance(s, str) for s in stages)
    # the library's check; it comes after the chain and 003's analysis (the
    # switch distances'), so on the compared run's small options, not the defaults' (minutes)
    with pytest.raises(jnd.JndError, match="lod: tolerance 20 outside"):
        jnd.lod("builtin", tmp_path / "x", tolerance=20, map_size=64, screens=["320x240@20"], judge_views=1, views=1,
                max_px=64, errors="1/256,1/64", no_textures=True, no_pop=True)
    with pytest.raises(jnd.JndError, match="--pop-motion: 'walk' is not orbit, spin or pan"):
        jnd.lod("builtin", tmp_path / "x", pop_motion="walk")
    with pytest.raises(jnd.JndError, match="lod: --screens: screen 'tv'"):
        jnd.lod("builtin", tmp_path / "x", screens="tv")
    assert not (tmp_path / "x").exists()


def test_render_from_python_is_the_commands_report(tmp_path, renderer):
    args = ["builtin", "--views", "2", "--size", "64x48", "--map-size", "64", "--outputs", "color,depth,mask",
            "--scale", "*=0.5", "--exposure", "1.5", "--background", "env"]
    r = same_as_cli(tmp_path, "render", args,
                    lambda out: jnd.render("builtin", out, views=2, size=(64, 48), map_size=64,
                                           outputs=["color", "depth", "mask"], scale="*=0.5", exposure=1.5,
                                           background="env"), report_name="views.json")
    assert r.report["command"] == "render"
    with pytest.raises(jnd.JndError, match="--outputs: 'rgb'"):
        jnd.render("builtin", tmp_path / "x", outputs="rgb")
    with pytest.raises(jnd.JndError, match="nope/baseColor: no such map"):   # the library's
        jnd.render("builtin", tmp_path / "x", scale="nope/baseColor=0.5", map_size=16, size="16x16")
    assert not (tmp_path / "x").exists()


def test_diff_run_from_python_is_the_commands_report_and_files(tmp_path, demo):
    ref, test = demo
    cli = subprocess.run([JND, "diff", ref, test, "--display", "phone", "--pool", "p99", "--heatmap",
                          str(tmp_path / "cli.png"), "--map", str(tmp_path / "cli.exr"), "--json",
                          str(tmp_path / "cli.json"), "--fail-above", "0.5", "--quiet"], env=CLI_ENV)
    r = jnd.diff_run(ref, test, display="phone", pool="p99", heatmap=tmp_path / "py.png", map=tmp_path / "py.exr",
                     json=tmp_path / "py.json", fail_above=0.5)
    assert r.report_text == (tmp_path / "cli.json").read_text() == (tmp_path / "py.json").read_text()
    for ext in ("png", "exr"):
        assert (tmp_path / f"py.{ext}").read_bytes() == (tmp_path / f"cli.{ext}").read_bytes()
    assert r.passes == (cli.returncode == 0) and r.p_detect == r.report["result"]["p_detect"]
    # the same comparison in memory
    assert jnd.diff(ref, test, display="phone", pooling="p99").p_detect == pytest.approx(r.p_detect, rel=1e-14)
    # never over an input: the library's refusal, nothing written
    before = open(ref, "rb").read()
    with pytest.raises(jnd.JndError, match="reference.png"):
        jnd.diff_run(ref, test, heatmap=ref, json=tmp_path / "no.json")
    assert open(ref, "rb").read() == before and not (tmp_path / "no.json").exists()



# csf, gaze (table, fit, observers), pop (asset, frames) and budget: the
# command's report byte for byte, the same files, progress and the GIL

def csf_set(folder):
    """A small castleCSF-format set: colour directions, a background and a
    few stimuli (luminance, cpd, direction, sigma, area, data set, Hz,
    eccentricity, kind, measured sensitivity)."""
    (folder / "color_directions.csv").write_text(
        "col_dir_id,L_delta,M_delta,S_delta,dataset\n"
        "1,0.918203011274591,0.395254682570263,0.0260185701481506,mine\n"
        "3,0.762860488743917,-0.646494144848117,-0.00944433112997181,mine\n")
    (folder / "backgrounds.csv").write_text(
        "bkg_id,L,M,S,bkg_label,dataset\n1,36.7372648518233,15.8141236515338,1.04100192534928,D65,mine\n")
    stimuli = [(50, 2, 1, 0.5, 0.785, "achromatic", 0, 0, "gabor", 200), (50, 8, 1, 0.5, 0.785, "achromatic", 0, 0,
               "gabor", 100), (50, 1, 3, 0.5, 0.785, "chromatic", 0, 0, "gabor", 300),
               (20, 4, 1, 1, 4, "moving", 8, 0, "grating", 60), (20, 4, 1, 1, 4, "peripheral", 0, 10, "grating", 30),
               (20, 4, 1, 1, 4, "foveal", 0, 0, "grating", 80)]
    head = ("luminance,s_frequency,col_dir_id,bkg_id,ge_sigma,area,N,log_cone_contrast,dataset,t_frequency,"
            "orientation,eccentricity,vis_field,stimulus,sensitivity")
    rows = [f"{lum},{sf},{col},1,{sigma},{area},1,{-math.log10(sens):.3f},{ds},{hz},0,{ecc},180,{kind},{sens}"
            for lum, sf, col, sigma, area, ds, hz, ecc, kind, sens in stimuli]
    (folder / "data.csv").write_text("\n".join([head, *rows]) + "\n")
    return str(folder / "data.csv")


def test_csf_from_python_is_the_commands_report_and_csv(tmp_path):
    data = csf_set(tmp_path)
    args = [data, "--set", "sensitivity=0.1", "--dataset", "achromatic", "--dataset", "foveal", "--fit",
            "--fit-only", "sensitivity", "--iterations", "3", "--min-band", "0.5"]
    stages = []
    r = same_as_cli(tmp_path, "csf", args,
                    lambda out: jnd.csf(data, out, set={"sensitivity": 0.1}, dataset=["achromatic", "foveal"], fit=True,
                                        fit_only="sensitivity", iterations=3, min_band=0.5,
                                        progress=lambda *a: stages.append(a)))
    assert r.report["command"] == "csf" and r.rows == 3 and r.passes is None
    assert r.report["parameters"]["constants"]["sensitivity"]["fitted"]
    assert stages and all(isinstance(line, str) and 0 <= done <= total for line, done, total in stages)
    # without an output CSV: the report only; "NAME=VALUE" strings set constants as the command's --set
    assert jnd.csf(data, set=["sensitivity=0.1"], dataset="achromatic").rows == 2
    with pytest.raises(jnd.JndError, match="csf: --set: no constant 'nonsense'"):
        jnd.csf(data, tmp_path / "x.csv", set={"nonsense": 1})
    with pytest.raises(jnd.JndError, match="--set: model: sensitivity must be in"):   # the library's bounds
        jnd.csf(data, tmp_path / "x.csv", set="sensitivity=-1")
    with pytest.raises(jnd.JndError, match="csf: --fit-only: no constant 'nope'"):
        jnd.csf(data, tmp_path / "x.csv", fit=True, fit_only=["sensitivity", "nope"])
    with pytest.raises(jnd.JndError, match="missing.csv"):
        jnd.csf(tmp_path / "missing.csv", tmp_path / "x.csv")
    assert not (tmp_path / "x.csv").exists()


GAZE = ["--map-size", "32", "--orientations", "1", "--distances", "20,80", "--eccentricities", "0,30", "--min-px", "32",
        "--max-px", "48"]
GAZE_KW = dict(map_size=32, orientations=1, distances=[20, 80], eccentricities="0,30", min_px=32, max_px=48)


def test_gaze_table_from_python_is_the_commands_report_with_the_gil_free(tmp_path, renderer):
    args = ["builtin:sphere", *GAZE, "--display", "phone", "--task", "flicker", "--seed", "3"]
    timing = []

    def call(out):
        result = []
        timing.append(ticks_during(lambda: result.append(
            jnd.gaze("builtin:sphere", out, display="phone", task="flicker", seed=3, **GAZE_KW))))
        return result[0]

    r = same_as_cli(tmp_path, "gaze", args, call)
    assert r.report["command"] == "gaze" and r.report["parameters"]["display"]["task"] == "flicker"
    seconds, during = timing[0]
    assert during >= 50, (seconds, during)   # no progress callback: the GIL is free for the whole run
    steps = []   # the progress of a run of one distance and one eccentricity
    jnd.gaze("builtin:sphere", tmp_path / "again", progress=lambda *a: steps.append(a),
             **{**GAZE_KW, "distances": [20], "eccentricities": [0]})
    assert steps and all(line is None and 0 <= done <= total for line, done, total in steps)
    assert steps[-1][1] == steps[-1][2]
    with pytest.raises(jnd.JndError, match=r"gaze: --size does not apply \(its views are --distances"):
        jnd.gaze("builtin:sphere", tmp_path / "x", size="64x64")
    with pytest.raises(jnd.JndError, match="--orientations: give 1 to 256"):   # the library's
        jnd.gaze("builtin:sphere", tmp_path / "x", orientations=0)
    with pytest.raises(jnd.JndError, match="--task: unknown viewing task 'blink'"):
        jnd.gaze("builtin:sphere", tmp_path / "x", task="blink")
    assert not (tmp_path / "x").exists()


def test_gaze_fit_and_observers_from_python_are_the_commands_reports(tmp_path, renderer):
    import random
    rng = random.Random(3)
    rows = ["t_jnd,seen"]
    for _ in range(40):
        t = 0.1 * 40 ** rng.random()
        p = 0.5 + 0.5 / (1 + (0.6 * t) ** -2.5)
        rows += [f"{t:.6f},{int(rng.random() < p)}" for _ in range(10)]
    trials = tmp_path / "trials.csv"
    trials.write_text("\n".join(rows) + "\n")
    r = same_as_cli(tmp_path, "gaze fit", [str(trials), "--folds", "3", "--seed", "2"],
                    lambda out: jnd.gaze_fit(trials, out, folds=3, seed=2), report_name="gaze_fit.json")
    assert r.report["command"] == "gaze fit" and r.passes is None
    assert jnd.gaze_fit(trials, folds=3, seed=2).report_text == r.report_text   # no folder: the report only
    with pytest.raises(jnd.JndError, match="--folds: give 2 to 16"):
        jnd.gaze_fit(trials, folds=40)
    obs = tmp_path / "obs"
    obs.mkdir()
    args = ["builtin:sphere", "--sizes", "4", "--eccentricities", "0,20", "--orientations", "1", "--answers", "5",
            "--min-px", "32", "--max-px", "48", "--map-size", "32"]
    steps = []
    r = same_as_cli(obs, "gaze observers", args,
                    lambda out: jnd.gaze_observers("builtin:sphere", out, sizes=[4], eccentricities=[0, 20],
                                                   orientations=1, answers=5, min_px=32, max_px=48, map_size=32,
                                                   progress=lambda *a: steps.append(a)),
                    report_name="observers.json")
    assert r.report["command"] == "gaze observers" and steps
    for name in ("spatial.csv", "temporal.csv"):
        assert (obs / "out" / name).read_text() == (obs / "cli" / name).read_text()


def test_pop_from_python_is_the_commands_report(tmp_path, renderer, demo):
    args = ["builtin", "--size", "64x64", "--views", "1", "--map-size", "64", "--errors", "0.1", "--orbit", "60",
            "--frame", "2", "--fail-above", "0.5", "--fps", "30"]
    stages = []
    r = same_as_cli(tmp_path, "pop", args,
                    lambda out: jnd.pop("builtin", out, size="64x64", views=1, map_size=64, errors=[0.1], orbit=60,
                                        frame=2, fail_above=0.5, fps=30, progress=lambda *a: stages.append(a[0])))
    cli = json.loads((tmp_path / "cli" / "pop.json").read_text())
    assert r.report["command"] == "pop" and r.passes == (cli["result"]["pair"]["max_rating"] <= 0.5
                                                         if "pair" in cli["result"] else r.passes)
    assert stages and all(isinstance(s, str) for s in stages)
    with pytest.raises(jnd.JndError, match="pop: give one of --orbit, --translate and --spin"):
        jnd.pop("builtin", tmp_path / "x", orbit=10, pan=10)
    with pytest.raises(jnd.JndError, match="pop: --direction: .* is not X,Y,Z"):
        jnd.pop("builtin", tmp_path / "x", translate=1, direction=(0, 0, 0))
    assert not (tmp_path / "x").exists()
    # the frame form, on the demo pair, seen flickering
    frames = tmp_path / "frames"
    frames.mkdir()
    new, expected = demo[1], demo[0]
    r = same_as_cli(frames, "pop", [new, expected, "--task", "flicker", "--max-regions", "3", "--maps",
                                    "--fail-above", "2"],
                    lambda out: jnd.pop_frames(new, expected, out, task="flicker", max_regions=3, maps=True,
                                               fail_above=2))
    assert r.report["parameters"]["display"]["task"] == "flicker"
    assert (frames / "out" / "jnd.exr").read_bytes() == (frames / "cli" / "jnd.exr").read_bytes()
    with pytest.raises(jnd.JndError, match="nope.png"):
        jnd.pop_frames(tmp_path / "nope.png", expected, tmp_path / "x")
    assert not (tmp_path / "x").exists()


def test_budget_from_python_is_the_commands_report(tmp_path, renderer):
    args = ["builtin:sphere", "--map-size", "64", "--size", "64x64", "--samples", "1", "--views", "2", "--confirm", "0",
            "--screens", "320x240", "--errors", "0.008,0.03", "--judge-views", "1", "--max-px", "64", "--tolerance",
            "0.5", "--far-coverage", "0.05", "--verify-views", "1", "--p", "0.3"]
    kw = dict(map_size=64, size="64x64", samples=1, views=2, confirm=0, screens=["320x240"], errors="0.008,0.03",
              judge_views=1, max_px=64, tolerance=0.5, far_coverage=0.05, verify_views=1, p=0.3)
    lines = []
    r = same_as_cli(tmp_path, "budget", args,
                    lambda out: jnd.budget("builtin:sphere", out, progress=lambda *a: lines.append(a), **kw))
    assert r.report["command"] == "budget" and r.passes is True
    assert any(line for line, _, _ in lines) and any(line is None for line, _, _ in lines)
    model = [f for f in files_of(tmp_path / "out") if f.endswith(".glb")]
    assert model and (tmp_path / "out" / model[0]).read_bytes() == (tmp_path / "cli" / model[0]).read_bytes()
    with pytest.raises(jnd.JndError, match="budget: --memory: '8 parsecs' is not a size above 0"):
        jnd.budget("builtin:sphere", tmp_path / "x", memory="8 parsecs")
    with pytest.raises(jnd.JndError, match="builtin:sphere: the bytes per triangle must be 0 or more"):   # the library's
        jnd.budget("builtin:sphere", tmp_path / "x", bytes_per_triangle=-1)
    assert not (tmp_path / "x").exists()


# the viewing task (jnd_display.task) from Python: the command's --task

def test_the_viewing_task_is_the_commands_task(tmp_path, demo):
    want = cli_diff(*demo, "--task", "flicker")
    flicker = jnd.display("standard-fhd", task="flicker")
    assert flicker.task == "flicker" and jnd.display("standard-fhd").task == "side-by-side"
    got = jnd.diff(*demo, display=flicker)
    assert got.p_detect == pytest.approx(want["p_detect"], rel=1e-14)
    assert got.p_detect != jnd.diff(*demo).p_detect   # the task changes P on the demo pair
    r = jnd.diff_run(*demo, task="flicker", json=tmp_path / "py.json")
    subprocess.run([JND, "diff", *demo, "--task", "flicker", "--json", str(tmp_path / "cli.json"), "--quiet"],
                   check=True, env=CLI_ENV)
    assert r.report_text == (tmp_path / "cli.json").read_text()
    with pytest.raises(jnd.JndError, match=r"unknown viewing task 'blink' \(side-by-side or flicker\)"):
        jnd.diff(*demo, display=jnd.display("phone", task="blink"))


def test_the_display_is_checked_by_the_library():
    """Every quantity of a display is the library's check (jnd_display_check),
    in its words: NaN, infinite, negative or out of range, from a
    jnd.Display or a task's keywords; the package checks none itself."""
    ref = np.full((16, 16), 0.5, np.float32)
    with pytest.raises(jnd.JndError, match=r"^display phone: pixels per degree must be in \[1, 1000\], not 0$"):
        jnd.Model(jnd.display("phone", ppd=0))
    with pytest.raises(jnd.JndError, match=r"^display phone: need 0 <= black \(0\.5\) < peak \(0\.4\) cd/m²$"):
        jnd.diff(ref, ref, display=jnd.display("phone", peak_cdm2=0.4))
    nan, inf = float("nan"), float("inf")
    for field, word in (("ppd", "pixels per degree"), ("peak_cdm2", "peak"), ("black_cdm2", "black"),
                        ("ambient_lux", "ambient"), ("reflectivity", "reflectivity"), ("exr_scale", "exr_scale"),
                        ("diagonal_in", "diagonal"), ("distance_m", "distance")):
        for bad in (nan, inf, -inf, -1.0):
            with pytest.raises(jnd.JndError) as e:
                jnd.diff(ref, ref, display=jnd.display("phone", **{field: bad}), encoding="linear")
            msg = str(e.value)
            assert msg.startswith("display phone: ") and word in msg and "\n" not in msg, (field, bad, msg)
            assert e.value.status == "JND_ERR_ARG"
    with pytest.raises(jnd.JndError, match=r"^display phone: exr_scale 0 is outside \[1e-09, 1e\+09\] cd/m² per unit$"):
        jnd.diff(ref, ref, display=jnd.display("phone", exr_scale=0), encoding="linear")
    # no check of the package's own is left in its source
    import inspect
    assert "exr_scale" not in inspect.getsource(jnd.Display._to_c)


def test_a_tasks_display_keywords_are_checked_by_the_library(tmp_path, demo):
    """The command's --ambient, --reflectivity, --exr-scale, --peak from
    Python: out of range, the library's line, nothing written; a display the
    command's parser lets through (black above peak) gets the same line from
    the command as from Python."""
    for kw, needle in ((dict(ambient=-1), "display standard-fhd: ambient -1 lux is outside [0, 200000]"),
                       (dict(reflectivity=2), "display standard-fhd: reflectivity 2 is outside [0, 1]"),
                       (dict(exr_scale=0), "display standard-fhd: exr_scale 0 is outside"),
                       (dict(display="phone", peak=1e6), "display phone: peak 1e+06 cd/m² is outside")):
        with pytest.raises(jnd.JndError) as e:
            jnd.diff_run(*demo, json=tmp_path / "out.json", **kw)
        assert needle in str(e.value), (kw, str(e.value))
    assert not (tmp_path / "out.json").exists()
    with pytest.raises(jnd.JndError) as e:
        jnd.diff_run(*demo, peak=0.5, black=1, json=tmp_path / "out.json")
    cli = subprocess.run([JND, "diff", *demo, "--peak", "0.5", "--black", "1", "--json", str(tmp_path / "out.json")],
                         capture_output=True, text=True, env=CLI_ENV)
    assert cli.returncode == 2 and cli.stderr.strip() == "jnd: " + str(e.value)
    assert "display standard-fhd: need 0 <= black (1) < peak (0.5) cd/m²" in str(e.value)
    assert not (tmp_path / "out.json").exists()
