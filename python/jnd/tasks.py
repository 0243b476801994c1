"""The tasks as calls: ``jnd.texres``, ``jnd.pca``, ``jnd.calibrate``.

Each is one library call, ``jnd_<task>_run(input, params, out, &result)``
(include/jnd.h, "The task shape"): it writes the task's folder (or file)
and report through the library's output writer — all or nothing, never over
an input — and returns the report's JSON text, which the result here holds
parsed. Keyword arguments are the command's long options with ``-`` spelled
``_`` (``--map-size 128`` is ``map_size=128``; a flag such as ``--quick-matrix``
is ``quick_matrix=True``); defaults are the library's, so a call and the
command line with the same options give the same report, byte for byte.

Options every rendering task shares (the command's option groups):

- views: ``views`` (count), ``seed``, ``size`` ("WxH" or (w, h), pixels),
  ``coverage``, ``distance`` (object units), ``fov`` (degrees),
  ``elevation`` ((a, b) degrees), ``lights``, ``light_intensity``,
  ``cameras`` (a JSON file), ``env`` (.hdr/.exr), ``samples``,
  ``anisotropy``, ``platform``, ``map_size`` (builtin asset's maps, pixels)
- display: ``display`` (a preset name or a :class:`jnd.Display`), ``ppd``,
  ``peak`` (cd/m²), ``black`` (cd/m²), ``ambient`` (lux),
  ``reflectivity``, ``exr_scale``
- criterion (texres, pca): ``p``, ``q``; ``pool`` ("p93"), ``calibration``
  (a ``jnd calibrate`` file)
- common: ``json`` (also write the report there), ``timings``, ``threads``

``progress``: a callable ``progress(line, done, total)`` — line is None after
each rendering and a one-line summary at the end of each stage; done counts
renderings (or scenes), total is an estimate. It runs on the thread that
made the call or on a library thread, with the GIL held. An exception it
raises cannot stop the run (the library has no cancel): later calls are
skipped and the exception is raised when the run returns. Warnings about
the input are in the result's ``warnings`` and issued as
:class:`JndWarning`. The GIL is released while the library works.
"""
from __future__ import annotations

import json as _json
import math
import os
import warnings as _warnings
from typing import Any, Callable, Optional, Sequence, Union

from ._jnd_cffi import ffi, lib

__all__ = ["TaskResult", "JndWarning", "texres", "pca", "calibrate"]

Progress = Optional[Callable[[Optional[str], int, int], Any]]


class JndWarning(UserWarning):
    """A warning of libjnd about an input (the command's "jnd: warning: ...")."""


class TaskResult:
    """A task's outcome: its attributes are the fields of the JSON report's
    "result" (``r.maps``, ``r.memory``, ...); ``report`` is the whole report
    (a dict), ``report_text`` its text as the library wrote it, ``passes``
    whether the choice passes the criterion (None where the task has no
    criterion), ``warnings`` the warnings about the input."""

    def __init__(self, report_text: str, passes: Optional[bool], warnings: list):
        self.report_text = report_text
        self.report = _json.loads(report_text)
        self.passes = passes
        self.warnings = warnings

    def __getattr__(self, name: str):
        result = self.__dict__.get("report", {}).get("result")
        if isinstance(result, dict) and name in result:
            return result[name]
        raise AttributeError(f"{type(self).__name__} has no field {name!r}")

    def __dir__(self):
        result = self.report.get("result")
        return sorted(set(super().__dir__()) | set(result if isinstance(result, dict) else ()))

    def __repr__(self):
        return f"<jnd {self.report.get('command', 'task')} result, passes={self.passes}>"


# ------------------------------------------------------------ callbacks --

class _RunState:
    def __init__(self, progress: Progress):
        self.progress = progress
        self.error: Optional[BaseException] = None
        self.warnings: list = []


def _callback_error(exc_type, exc, tb):
    # reached only if storing the exception itself failed: nothing to keep
    return None


@ffi.def_extern(onerror=_callback_error)
def _jnd_progress(user, line, done, total):
    state = ffi.from_handle(user)
    if state.error is not None:
        return
    try:
        state.progress(None if line == ffi.NULL else ffi.string(line).decode("utf-8", "replace"), done, total)
    except BaseException as e:   # kept for the caller: an exception cannot cross the C library
        state.error = e


@ffi.def_extern(onerror=_callback_error)
def _jnd_warning(user, message):
    state = ffi.from_handle(user)
    state.warnings.append(ffi.string(message).decode("utf-8", "replace"))


# ---------------------------------------------------------- option groups --

class _Options:
    """Sets a params struct from keyword arguments with the command's names,
    limits and messages; keeps the C strings alive for the call."""

    def __init__(self, task: str, kw: dict):
        self.task, self.kw, self.keep = task, dict(kw), []

    def has(self, name: str) -> bool:
        return self.kw.get(name) is not None

    def take(self, name: str):
        return self.kw.pop(name, None)

    def _bad(self, message: str):
        from . import JndError
        raise JndError(message)

    def cstr(self, value) -> Any:
        s = ffi.new("char[]", os.fsencode(value) if isinstance(value, (str, bytes, os.PathLike)) else
                    str(value).encode())
        self.keep.append(s)
        return s

    def number(self, name: str, lo: float, hi: float, integer: bool = False):
        v = self.take(name)
        if v is None:
            return None
        opt = "--" + name.replace("_", "-")
        try:
            x = float(v)
        except (TypeError, ValueError):
            self._bad(f"{opt}: '{v}' is not a number")
        if not math.isfinite(x):
            self._bad(f"{opt}: '{v}' is not a number")
        if integer and (isinstance(v, bool) or not x.is_integer()):
            self._bad(f"{opt}: '{v}' is not an integer")
        if x < lo or x > hi:
            self._bad(f"{opt}: {x:g} is outside [{lo:g}, {hi:g}]")
        return int(x) if integer else x

    def ints(self, name: str, lo: int, hi: int, max_n: int = 64) -> Optional[list]:
        v = self.take(name)
        if v is None:
            return None
        opt = "--" + name.replace("_", "-")
        items = v.split(",") if isinstance(v, str) else list(v)
        try:
            out = [int(str(x).strip()) for x in items]
        except ValueError:
            out = None
        if not out or len(out) > max_n or any(not lo <= x <= hi for x in out):
            self._bad(f"{opt}: '{v}' is not a list of at most {max_n} integers in {lo}..{hi} like 1024,512,256")
        return out

    def int_array(self, values: list):
        a = ffi.new("int[]", values)
        self.keep.append(a)
        return a

    def pair(self, name: str):
        v = self.take(name)
        if v is None:
            return None
        try:
            a, b = (float(x) for x in (v.split(",") if isinstance(v, str) else v))
            if math.isfinite(a) and math.isfinite(b):
                return a, b
        except (TypeError, ValueError):
            pass
        self._bad(f"--{name.replace('_', '-')}: '{v}' is not a pair of numbers like 10,20")

    # -- views (the command's --views ... --map-size; src/cli/args.c limits)
    def views(self, vs, run=None):
        s, r = vs.sampling, vs.render
        n = self.number("views", 1, 4096, True)
        if n is not None:
            s.count = n
        seed = self.number("seed", 0, 9007199254740992.0)
        if seed is not None:
            s.seed = int(seed)
        size = self.take("size")
        if size is not None:
            try:
                w, h = ((int(x) for x in size.lower().split("x")) if isinstance(size, str) else size)
            except (TypeError, ValueError):
                w = h = -1
            if not (16 <= w <= 16384 and 16 <= h <= 16384):
                self._bad(f"--size: '{size}' is not WxH with W and H in 16..16384 pixels")
            r.width, r.height = w, h
        for name, field, lo, hi in (("coverage", "coverage", 0.01, 10), ("distance", "distance", 1e-9, 1e12),
                                    ("fov", "fov_y_deg", 0.1, 179), ("light_intensity", "light_intensity", 0, 1e6)):
            x = self.number(name, lo, hi)
            if x is not None:
                setattr(s, field, x)
        lights = self.number("lights", 0, 8, True)
        if lights is not None:
            s.lights = lights
        el = self.pair("elevation")
        if el is not None:
            if not (-90 <= el[0] <= el[1] <= 90):
                self._bad(f"--elevation: '{el[0]:g},{el[1]:g}' is not A,B with -90 <= A <= B <= 90 degrees")
            s.min_elevation_deg, s.max_elevation_deg = el
        if self.has("cameras"):
            vs.cameras_path = self.cstr(self.take("cameras"))
        if self.has("env"):
            r.env_path = self.cstr(self.take("env"))
        for name, lo, hi in (("samples", 1, 64), ("anisotropy", 1, 16)):
            x = self.number(name, lo, hi, True)
            if x is not None:
                setattr(r, name, x)
        platform = self.take("platform")
        if platform is not None:
            if platform not in ("auto", "device", "surfaceless"):
                self._bad(f"--platform: '{platform}' is not auto, device or surfaceless")
            r.platform = self.cstr(platform)
        map_size = self.number("map_size", 8, 8192, True)
        return 2048 if map_size is None else map_size

    # -- display (cli_display_get: an explicit quantity wins over the preset's)
    def display(self, model_params):
        from . import Display, display as preset
        d = self.take("display")
        disp = preset(d) if isinstance(d, str) else preset() if d is None else d
        if not isinstance(disp, Display):
            self._bad(f"--display: a preset name or a jnd.Display, not {type(d).__name__}")
        vals = {k: self.number(k, lo, hi) for k, lo, hi in (
            ("ppd", 1, 1000), ("peak", 0.01, 100000), ("black", 0, 10000), ("ambient", 0, 200000),
            ("reflectivity", 0, 1), ("exr_scale", 1e-9, 1e9))}
        c = disp._to_c()
        if vals["ppd"] is not None:
            c.ppd, c.diagonal_in, c.distance_m, c.width_px, c.height_px = vals["ppd"], 0, 0, 0, 0
        if vals["peak"] is not None:
            if vals["black"] is None and abs(c.black_cdm2 - c.peak_cdm2 / 1000) < 1e-12:
                c.black_cdm2 = vals["peak"] / 1000
            c.peak_cdm2 = vals["peak"]
        for k, field in (("black", "black_cdm2"), ("ambient", "ambient_lux"), ("reflectivity", "reflectivity"),
                         ("exr_scale", "exr_scale")):
            if vals[k] is not None:
                setattr(c, field, vals[k])
        model_params.display = c[0]
        threads = self.number("threads", 1, 1024, True)
        if threads is not None:
            model_params.threads = threads

    # -- criterion and calibration (cli_criterion_opt, cli_calibration_get)
    def criterion(self, judge):
        p = self.number("p", 1e-6, 1 - 1e-6)
        if p is not None:
            judge.criterion.p = p
        q = self.number("q", 0, 0.999)
        if q is not None:
            judge.criterion.q = q
        from . import _check
        lib.jnd_calibration_defaults(ffi.addressof(judge.calibration))
        path = self.take("calibration")
        if path is not None:
            _check(lib.jnd_calibration_load(self.cstr(path), ffi.addressof(judge.calibration)))
        pool = self.take("pool")
        if pool is not None:
            pp = ffi.new("jnd_pooling *")
            if lib.jnd_pooling_parse(str(pool).encode(), pp) != lib.JND_OK or pp.kind != lib.JND_POOL_PERCENTILE:
                self._bad(f"--pool: '{pool}' is not a percentile like p93")
            judge.calibration.percentile = pp.percentile

    def run_options(self, run, map_size: int):
        run.map_size = map_size
        path = self.take("json")
        if path is not None and path != "-":
            run.report_path = self.cstr(path)
        self.print_report = path == "-"
        run.timings = 1 if self.take("timings") else 0

    def done(self):
        if self.kw:
            raise TypeError(f"{self.task}() got unexpected keyword argument(s): {', '.join(sorted(self.kw))}")


def _run(task: str, opts: _Options, fn, free, input_path, params, out_path, progress: Progress,
         has_passes: bool) -> TaskResult:
    """One call of jnd_<task>_run with the callbacks into Python; the result
    freed, callback exceptions re-raised, errors as JndError."""
    from . import _check
    state = _RunState(progress)
    handle = ffi.new_handle(state)
    if progress is not None:   # else no call back into Python (and no GIL) per rendering
        params.progress, params.progress_user = lib._jnd_progress, handle
    params.run.warning, params.run.warning_user = lib._jnd_warning, handle
    out = ffi.new(f"jnd_{task}_result **")
    c_in = ffi.NULL if input_path is None else opts.cstr(input_path)
    status = fn(c_in, params, opts.cstr(out_path), out)
    try:
        if state.error is not None:
            raise state.error
        _check(status)
        text = ffi.string(out[0].report).decode("utf-8")
        passes = bool(out[0].passes) if has_passes else None
    finally:
        free(out[0])
    for w in state.warnings:
        _warnings.warn(w, JndWarning, stacklevel=3)
    if opts.print_report:
        print(text)
    return TaskResult(text, passes, state.warnings)


PathLike = Union[str, os.PathLike]


def texres(model: PathLike, out_dir: PathLike, *, verify_views: Optional[int] = None,
           margin: Optional[float] = None, confirm: Optional[int] = None, sizes: Union[str, Sequence[int], None] = None,
           min_size: Optional[int] = None, maps: Union[str, Sequence[str], None] = None, matrix: bool = False,
           quick_matrix: bool = False, progress: Progress = None, **options) -> TaskResult:
    """``jnd texres MODEL -o OUT_DIR``: the smallest texture maps nobody
    notices (000 §4–§9, docs/texres.md). model: a .gltf/.glb/.obj file or
    "builtin"; out_dir gets texres.json, worst_view.png and model/ or maps/.
    verify_views: held-out views (0); margin: choose with P·(1 − margin)
    (0.5); confirm: fresh view sets that must agree (2); sizes: candidate
    sizes, longer side in pixels; min_size: floor of the halvings (32);
    maps: the maps to search (MATERIAL/SLOT or slot names; default all);
    matrix / quick_matrix: the baseColor × normal matrix. Shared options
    (views, display, criterion, common): see the module's help. The result's
    ``passes`` is False where the choice fails the criterion (the command's
    exit status 1)."""
    o = _Options("texres", options)
    p = ffi.new("jnd_texres_params *")
    lib.jnd_texres_defaults(p)
    map_size = o.views(p.judge.views)
    o.display(p.judge.model)
    o.criterion(p.judge)
    o.run_options(p.run, map_size)
    o.kw.update(verify_views=verify_views, margin=margin, confirm=confirm, sizes=sizes, min_size=min_size)
    for name, field, lo, hi, integer in (("verify_views", "verify_views", 0, 4096, True),
                                         ("margin", "margin", 0, 0.99, False),
                                         ("confirm", "confirm_rounds", 0, 16, True),
                                         ("min_size", "min_size", 1, 32768, True)):
        x = o.number(name, lo, hi, integer)
        if x is not None:
            setattr(p, field, x)
    s = o.ints("sizes", 1, 32768)
    if s is not None:
        p.sizes, p.nsizes = o.int_array(s), len(s)
    if maps is not None:
        p.maps = o.cstr(maps if isinstance(maps, str) else ",".join(maps))
    p.matrix = 2 if matrix else 1 if quick_matrix else 0
    o.done()
    return _run("texres", o, lib.jnd_texres_run, lib.jnd_texres_result_free, model, p, out_dir, progress, True)


def pca(maps: Sequence[PathLike], out_dir: PathLike, *, model: Optional[PathLike] = None,
        material: Optional[str] = None, components: Union[int, str, None] = None, energy: Optional[float] = None,
        psnr: Optional[float] = None, bits: Union[str, Sequence[int], None] = None,
        resolutions: Union[str, Sequence[int], None] = None, max_scale: Optional[int] = None,
        slot: Sequence[str] = (), channels: Optional[str] = None, weight: Optional[str] = None,
        write_maps: bool = False, no_bc: bool = False, progress: Progress = None, **options) -> TaskResult:
    """``jnd pca MAPS... -o OUT_DIR``: the cheapest principal-component
    encoding of a set of maps (docs/pca.md). maps: map files (may be empty
    with model=); model, material: a model using the set, for the rendered
    rule; components ("all" or K), energy (fraction of variance), psnr (dB):
    one rule; bits: 8 or 16 per component; resolutions: size divisor per
    component (powers of two up to 8); max_scale; slot: "FILE=SLOT" strings;
    channels, weight: as the command's --channels, --weight; write_maps:
    also the rebuilt maps; no_bc: no block compression. Shared options
    (views, display, criterion, common): see the module's help."""
    from . import JndError
    o = _Options("pca", options)
    p = ffi.new("jnd_pca_params *")
    lib.jnd_pca_defaults(p)
    criterion_given = o.has("p") or o.has("q")
    map_size = o.views(p.render.judge.views)
    o.display(p.render.judge.model)
    o.criterion(p.render.judge)
    o.run_options(p.run, map_size)
    maps = [os.fspath(m) for m in ([maps] if isinstance(maps, (str, os.PathLike)) else maps or [])]
    if len(maps) > 16:
        raise JndError("pca: at most 16 maps")
    rules = 0
    if components is not None:
        if components == "all":
            p.components = -1
        else:
            o.kw["components"] = components
            p.components = o.number("components", 0, 32, True)
        p.rule, rules = lib.JND_PCA_RULE_COMPONENTS, rules + 1
    if energy is not None:
        o.kw["energy"] = energy
        p.energy, p.rule, rules = o.number("energy", 1e-6, 1), lib.JND_PCA_RULE_ENERGY, rules + 1
    if psnr is not None:
        o.kw["psnr"] = psnr
        p.psnr_db, p.rule, rules = o.number("psnr", 1, 150), lib.JND_PCA_RULE_PSNR, rules + 1
    if bits is not None:
        o.kw["bits"] = bits
        b = o.ints("bits", 8, 16, 32)
        if any(x not in (8, 16) for x in b):
            raise JndError(f"--bits: {next(x for x in b if x not in (8, 16))} (8 or 16 per component)")
        p.bits[0:len(b)], p.nbits = b, len(b)
    if resolutions is not None:
        o.kw["resolutions"] = resolutions
        d = o.ints("resolutions", 1, 8, 32)
        for x in d:
            if x & (x - 1):
                raise JndError(f"--resolutions: {x} is not a power of two up to 8")
        p.scale[0:len(d)], p.nscale = [x.bit_length() - 1 for x in d], len(d)
    if max_scale is not None:
        o.kw["max_scale"] = max_scale
        p.max_scale = o.number("max_scale", 0, 3, True)
    if model is not None:
        p.model = o.cstr(model)
    if material is not None:
        p.material = o.cstr(material)
    if channels is not None:
        p.channels = o.cstr(channels)
    if weight is not None:
        p.weights = o.cstr(weight)
    slot = [slot] if isinstance(slot, str) else list(slot)
    if rules > 1:
        raise JndError("pca: give one of --components, --energy, --psnr")
    if criterion_given and model is None:
        raise JndError("pca: --p and --q judge renderings: they need --model FILE.glb and --material NAME")
    if (p.nbits or p.nscale) and p.rule == lib.JND_PCA_RULE_AUTO:
        p.rule = lib.JND_PCA_RULE_COMPONENTS
    if (p.nbits or p.nscale) and p.rule != lib.JND_PCA_RULE_COMPONENTS:
        raise JndError("pca: --bits and --resolutions go with --components")
    if not maps and model is None:
        raise JndError("pca: needs maps (or --model) and -o OUTDIR (jnd pca --help)")
    if model is not None and material is None:
        raise JndError("pca: --model needs --material NAME")
    if slot and not (model is not None and maps):
        raise JndError("pca: --slot needs MAP files and --model")
    c_maps = [o.cstr(m) for m in maps]
    c_slots = [o.cstr(s) for s in slot]
    p.maps, p.nmaps = _char_array(o, c_maps), len(c_maps)
    p.slots, p.nslots = _char_array(o, c_slots), len(c_slots)
    p.render.builtin_map_size = map_size
    p.write_maps = 1 if write_maps else 0
    if no_bc:
        p.block_compression = 0
    o.done()
    return _run("pca", o, lib.jnd_pca_run, lib.jnd_pca_result_free, model, p, out_dir, progress, False)


def _char_array(o: _Options, strings: list):
    a = ffi.new("const char *[]", strings + [ffi.NULL])
    o.keep.append(a)
    return a


def calibrate(thresholds_csv: PathLike, out_path: PathLike, *, pairs: Optional[PathLike] = None,
              sizes: Union[str, Sequence[int], None] = None, folds: Optional[int] = None, p: Optional[float] = None,
              bias_range: Optional[Sequence[float]] = None, histogram: Optional[PathLike] = None,
              progress: Progress = None, **options) -> TaskResult:
    """``jnd calibrate THRESHOLDS.csv -o CAL.json``: fits the pooling
    percentile and a JND transform to measured thresholds (000 §6–§7,
    docs/calibrate.md) and writes the calibration file (the report) at
    out_path. pairs: a CSV of image pairs; sizes: an asset's series sizes;
    folds: k of the cross-validation (5); p: the P at which thresholds are
    compared (0.2); bias_range: (a, b) JND; histogram: also this PNG. Shared
    options (views, display, common): see the module's help."""
    from . import JndError
    o = _Options("calibrate", options)
    c = ffi.new("jnd_calibrate_run_params *")
    lib.jnd_calibrate_run_defaults(c)
    map_size = o.views(c.judge.views)
    o.display(c.judge.model)
    o.run_options(c.run, map_size)
    o.kw.update(sizes=sizes, folds=folds, p=p, bias_range=bias_range)
    s = o.ints("sizes", 1, 32768)
    if s is not None:
        c.sizes, c.nsizes = o.int_array(s), len(s)
    k = o.number("folds", 1, 32, True)
    if k is not None:
        c.fit.folds = k
    tp = o.number("p", 0.01, 0.99)
    if tp is not None:
        c.fit.threshold_p = tp
    br = o.pair("bias_range")
    if br is not None:
        if not br[1] > br[0]:
            raise JndError(f"calibrate: --bias-range: '{br[0]:g},{br[1]:g}' needs A < B")
        c.fit.bias_min, c.fit.bias_max = br
    if pairs is not None:
        c.pairs = o.cstr(pairs)
    if histogram is not None:
        c.histogram = o.cstr(histogram)
    o.done()
    return _run("calibrate", o, lib.jnd_calibrate_run, lib.jnd_calibrate_result_free, thresholds_csv, c, out_path,
                progress, False)
