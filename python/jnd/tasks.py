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
  ``reflectivity``, ``exr_scale``, ``task`` ("side-by-side" or "flicker")
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
from fractions import Fraction
import warnings as _warnings
from typing import Any, Callable, Optional, Sequence, Union

from ._jnd_cffi import ffi, lib

__all__ = ["TaskResult", "JndWarning", "texres", "pca", "calibrate", "lod", "render", "diff_run", "csf", "gaze",
           "gaze_fit", "gaze_observers", "pop", "pop_frames", "budget"]

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
def _jnd_progress_count(user, done, total):
    """The progress of a run that counts steps only (gaze's table and observers)."""
    _jnd_progress(user, ffi.NULL, done, total)


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

    def give(self, **named):
        """The function's own keyword parameters, read as the options are
        (those left None are not given)."""
        self.kw.update({k: v for k, v in named.items() if v is not None})

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

    def number(self, name: str, lo: Optional[float] = None, hi: Optional[float] = None, integer: bool = False):
        """The keyword as a number, with the command's message where it is
        not one. lo, hi: a range only where the library does not check the
        field itself (it says what is wrong, in one line, for the others)."""
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
        if integer and abs(x) > 2**31 - 1:
            self._bad(f"{opt}: {x:g} is outside [{-2**31 + 1}, {2**31 - 1}]")
        if lo is not None and not lo <= x <= hi:
            self._bad(f"{opt}: {x:g} is outside [{lo:g}, {hi:g}]")
        return int(x) if integer else x

    def numbers(self, name: str, integer: bool, max_n: int = 64, lo: Optional[float] = None,
                hi: Optional[float] = None) -> Optional[list]:
        """A list keyword ("1024,512" or a sequence) as numbers; fractions
        such as "1/1024" are numbers too (--errors). lo, hi: as number()."""
        v = self.take(name)
        if v is None:
            return None
        opt = "--" + name.replace("_", "-")
        items = v.split(",") if isinstance(v, str) else [v] if isinstance(v, (int, float)) else list(v)
        try:
            out = [float(Fraction(str(x).strip())) for x in items]
        except (ValueError, ZeroDivisionError):
            out = None
        if (not out or len(out) > max_n or (integer and any(not x.is_integer() for x in out)) or
                (lo is not None and any(not lo <= x <= hi for x in out))):
            kind = ("integers" if integer else "numbers") + ("" if lo is None else f" in {lo:g}..{hi:g}")
            self._bad(f"{opt}: '{v}' is not a list of at most {max_n} {kind} like "
                      f"{'1024,512,256' if integer else '0.5,0.25,1/16'}")
        return [int(x) for x in out] if integer else out

    def array(self, ctype: str, values: list):
        a = ffi.new(f"{ctype}[]", values)
        self.keep.append(a)
        return a

    def choice(self, name: str, choices: dict):
        """A keyword that names one of choices (a value as the command's
        option takes it), mapped to the library's value."""
        v = self.take(name)
        if v is None:
            return None
        if v not in choices:
            self._bad(f"--{name.replace('_', '-')}: '{v}' is not {_one_of(list(choices))}")
        return choices[v]

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

    # -- views (the command's --views ... --map-size). The library checks the
    #    count, size, coverage, fov, lights, elevation, platform and map size;
    #    the ranges here are of the fields it takes as they come.
    def views(self, vs, defaults: Optional[dict] = None):
        """Sets a jnd_view_set; returns the builtin asset's map size."""
        s, r = vs.sampling, vs.render
        n = self.number("views", integer=True)
        if n is not None:
            s.count = n
        seed = self.number("seed", 0, 9007199254740992.0)
        if seed is not None:
            s.seed = int(seed)
        if self.has("size"):   # the library takes any size: the vision model's least, the renderer's most
            r.width, r.height = self._size("size", self.take("size"), 16, 16384)
        for name, field, lo, hi in (("coverage", "coverage", None, None), ("distance", "distance", 1e-9, 1e12),
                                    ("fov", "fov_y_deg", None, None), ("light_intensity", "light_intensity", 0, 1e6)):
            x = self.number(name, lo, hi)
            if x is not None:
                setattr(s, field, x)
        lights = self.number("lights", integer=True)
        if lights is not None:
            s.lights = lights
        el = self.pair("elevation")
        if el is not None:
            s.min_elevation_deg, s.max_elevation_deg = el
        if self.has("cameras"):
            vs.cameras_path = self.cstr(self.take("cameras"))
        if self.has("env"):
            r.env_path = self.cstr(self.take("env"))
        for name, lo, hi in (("samples", 1, 64), ("anisotropy", 1, 16)):
            x = self.number(name, lo, hi, True)
            if x is not None:
                setattr(r, name, x)
        if self.has("platform"):
            r.platform = self.cstr(self.take("platform"))
        map_size = self.number("map_size", integer=True)
        return (defaults or {}).get("map_size", 2048) if map_size is None else map_size

    def _size(self, name, v, lo, hi):
        """ "WxH" (or a pair) as two integers in lo..hi (a size the library
        takes as it comes)."""
        try:
            w, h = ((int(x) for x in v.lower().split("x")) if isinstance(v, str) else v)
            if lo <= w <= hi and lo <= h <= hi:
                return w, h
        except (TypeError, ValueError):
            pass
        self._bad(f"--{name}: '{v}' is not WxH with W and H in {lo}..{hi} pixels")

    # -- display (cli_display_get: an explicit quantity wins over the preset's;
    #    the library checks every quantity, jnd_display_check; task: "side-by-side" or "flicker")
    def display(self, model_params, set_threads: bool = True) -> bool:
        """Sets model_params.display; returns whether exr_scale was given."""
        from . import Display, display as preset
        d = self.take("display")
        disp = preset(d) if isinstance(d, str) else preset() if d is None else d
        if not isinstance(disp, Display):
            self._bad(f"--display: a preset name or a jnd.Display, not {type(d).__name__}")
        vals = {k: self.number(k) for k in ("ppd", "peak", "black", "ambient", "reflectivity", "exr_scale")}
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
        task = self.take("task")
        if task is not None:
            from . import _check
            t = ffi.new("jnd_viewing_task *")
            _check(lib.jnd_viewing_task_parse(str(task).encode(), t), "--task: ")
            c.task = t[0]
        model_params.display = c[0]
        if set_threads:
            self.threads(model_params)
        return vals["exr_scale"] is not None

    def threads(self, target):
        n = self.number("threads", 1, 1024, True)
        if n is not None:
            target.threads = n
        return n

    # -- criterion (the judge checks p and q) and calibration
    def criterion(self, crit):
        for name in ("p", "q"):
            x = self.number(name)
            if x is not None:
                setattr(crit, name, x)

    def calibration(self, judge):
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

    def run_options(self, run, map_size: int = 0):
        run.map_size = map_size
        path = self.take("json")
        if path is not None and path != "-":
            run.report_path = self.cstr(path)
        self.print_report = path == "-"
        run.timings = 1 if self.take("timings") else 0

    def views_only(self, allowed: tuple, cmd: str, why: str):
        """The view options a task has no use for are refused, in the
        command's order and words (cli_views_only)."""
        for name in ("views", "seed", "size", "coverage", "distance", "fov", "elevation", "lights",
                     "light_intensity", "cameras", "env", "samples", "anisotropy", "platform", "map_size"):
            if name not in allowed and self.has(name):
                self._bad(f"{cmd}: --{name.replace('_', '-')} does not apply ({why})")

    def chain(self):
        """A jnd_lod_params with the errors keyword as its targets (a plain
        mesh's chain; the command's range), or NULL without it."""
        e = self.numbers("errors", False, 63, 1e-6, 1)
        if e is None:
            return ffi.NULL
        c = ffi.new("jnd_lod_params *")
        lib.jnd_lod_defaults(c)
        c.errors, c.nerrors = self.array("double", e), len(e)
        self.keep.append(c)
        return c

    def done(self):
        if self.kw:
            raise TypeError(f"{self.task}() got unexpected keyword argument(s): {', '.join(sorted(self.kw))}")


def _one_of(names: list) -> str:
    return ", ".join(names[:-1]) + " or " + names[-1] if len(names) > 1 else names[0]


def _run(task: str, opts: _Options, call, free, params, progress: Progress, has_passes: bool,
         result: str = None, progress_at=None) -> TaskResult:
    """One call of the library's run, call(params, &result), with the
    callbacks into Python; the result freed, callback exceptions re-raised,
    errors as JndError. progress_at: where the run takes its progress
    callback, (struct, callback field, user field, counts_only) tuples
    (default: params.progress and params.progress_user, where it has them)."""
    from . import _check
    state = _RunState(progress)
    handle = ffi.new_handle(state)
    if progress_at is None:
        progress_at = [(params, "progress", "progress_user", False)] if hasattr(params, "progress") else []
    if progress is not None:   # else no call into Python per rendering
        for target, field, user, counts_only in progress_at:
            setattr(target, field, lib._jnd_progress_count if counts_only else lib._jnd_progress)
            setattr(target, user, handle)
    params.run.warning, params.run.warning_user = lib._jnd_warning, handle
    out = ffi.new(f"{result or f'jnd_{task}_result'} **")
    status = call(params, out)
    try:
        if state.error is not None:
            raise state.error
        _check(status)
        text = ffi.string(out[0].report).decode("utf-8")
        passes = None
        if has_passes:
            passes = bool(out[0].passes) if hasattr(out[0], "passes") else not out[0].above
    finally:
        free(out[0])
    for w in state.warnings:
        _warnings.warn(w, JndWarning, stacklevel=3)
    if opts.print_report:
        print(text)
    return TaskResult(text, passes, state.warnings)


def _run_shape(task: str, opts: _Options, params, input_path, out_path, progress: Progress,
               has_passes: bool = False, result: str = None, progress_at=None) -> TaskResult:
    """The task shape, jnd_<task>_run(input, params, out, &result); result:
    the result's type where it is not jnd_<task>_result (its free function
    is the type's name with _free)."""
    c_in = ffi.NULL if input_path is None else opts.cstr(input_path)
    c_out = ffi.NULL if out_path is None else opts.cstr(out_path)
    result = result or f"jnd_{task}_result"
    fn, free = getattr(lib, f"jnd_{task}_run"), getattr(lib, f"{result}_free")
    return _run(task, opts, lambda p, out: fn(c_in, p, c_out, out), free, params, progress, has_passes, result,
                progress_at)


PathLike = Union[str, os.PathLike]
IntList = Union[str, Sequence[int], None]


def texres(model: PathLike, out_dir: PathLike, *, verify_views: Optional[int] = None,
           margin: Optional[float] = None, confirm: Optional[int] = None, sizes: IntList = None,
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
    o.criterion(p.judge.criterion)
    o.calibration(p.judge)
    o.run_options(p.run, map_size)
    o.give(verify_views=verify_views, margin=margin, confirm=confirm, sizes=sizes, min_size=min_size)
    for name, field, integer in (("verify_views", "verify_views", True), ("margin", "margin", False),
                                 ("confirm", "confirm_rounds", True), ("min_size", "min_size", True)):
        x = o.number(name, integer=integer)   # the library checks each
        if x is not None:
            setattr(p, field, x)
    s = o.numbers("sizes", True, 64, 1, 32768)
    if s is not None:
        p.sizes, p.nsizes = o.array("int", s), len(s)
    if maps is not None:
        p.maps = o.cstr(maps if isinstance(maps, str) else ",".join(maps))
    p.matrix = 2 if matrix else 1 if quick_matrix else 0
    o.done()
    return _run_shape("texres", o, p, model, out_dir, progress, has_passes=True)


def pca(maps: Sequence[PathLike], out_dir: PathLike, *, model: Optional[PathLike] = None,
        material: Optional[str] = None, components: Union[int, str, None] = None, energy: Optional[float] = None,
        psnr: Optional[float] = None, bits: IntList = None, resolutions: IntList = None,
        max_scale: Optional[int] = None, slot: Sequence[str] = (), channels: Optional[str] = None,
        weight: Optional[str] = None, write_maps: bool = False, no_bc: bool = False, progress: Progress = None,
        **options) -> TaskResult:
    """``jnd pca MAPS... -o OUT_DIR``: the cheapest principal-component
    encoding of a set of maps (docs/pca.md). maps: map files (may be empty
    with model=); model, material: a model using the set, for the rendered
    rule; components ("all" or K), energy (fraction of variance), psnr (dB):
    one rule; bits: 8 or 16 per component; resolutions: size divisor per
    component (powers of two up to 8); max_scale; slot: "FILE=SLOT" strings;
    channels, weight: as the command's --channels, --weight; write_maps:
    also the rebuilt maps; no_bc: no block compression. Shared options
    (views, display, criterion, common): see the module's help. The library
    checks the maps, the model and material, --slot, the energy, the bits
    and the divisors, with its one-line messages."""
    from . import JndError
    o = _Options("pca", options)
    p = ffi.new("jnd_pca_params *")
    lib.jnd_pca_defaults(p)
    criterion_given = o.has("p") or o.has("q")
    map_size = o.views(p.render.judge.views)
    o.display(p.render.judge.model)
    o.criterion(p.render.judge.criterion)
    o.calibration(p.render.judge)
    o.run_options(p.run, map_size)
    maps = [os.fspath(m) for m in ([maps] if isinstance(maps, (str, os.PathLike)) else maps or [])]
    if sum(x is not None for x in (components, energy, psnr)) > 1:
        raise JndError("pca: give one of --components, --energy, --psnr")
    o.give(components=None if components == "all" else components, energy=energy, psnr=psnr,
                max_scale=max_scale)
    if components is not None:
        p.rule = lib.JND_PCA_RULE_COMPONENTS
        p.components = -1 if components == "all" else o.number("components", integer=True)
    if energy is not None:
        p.energy, p.rule = o.number("energy"), lib.JND_PCA_RULE_ENERGY
    if psnr is not None:
        p.psnr_db, p.rule = o.number("psnr", 1, 150), lib.JND_PCA_RULE_PSNR
    o.give(bits=bits, resolutions=resolutions)
    b = o.numbers("bits", True, 32)
    if b is not None:
        p.bits[0:len(b)], p.nbits = b, len(b)
    d = o.numbers("resolutions", True, 32)
    if d is not None:   # divisors as the library's scale exponents
        bad = next((x for x in d if x < 1 or x & (x - 1)), None)
        if bad is not None:
            raise JndError(f"--resolutions: {bad} is not a power of two up to 8")
        p.scale[0:len(d)], p.nscale = [x.bit_length() - 1 for x in d], len(d)
    x = o.number("max_scale", integer=True)
    if x is not None:
        p.max_scale = x
    for value, field in ((model, "model"), (material, "material"), (channels, "channels"), (weight, "weights")):
        if value is not None:
            setattr(p, field, o.cstr(value))
    if criterion_given and model is None:
        raise JndError("pca: --p and --q judge renderings: they need --model FILE.glb and --material NAME")
    if (p.nbits or p.nscale) and p.rule == lib.JND_PCA_RULE_AUTO:
        p.rule = lib.JND_PCA_RULE_COMPONENTS
    if (p.nbits or p.nscale) and p.rule != lib.JND_PCA_RULE_COMPONENTS:
        raise JndError("pca: --bits and --resolutions go with --components")
    slot = [slot] if isinstance(slot, str) else list(slot)
    p.maps, p.nmaps = _char_array(o, [o.cstr(m) for m in maps]), len(maps)
    p.slots, p.nslots = _char_array(o, [o.cstr(s) for s in slot]), len(slot)
    p.render.builtin_map_size = map_size
    p.write_maps = 1 if write_maps else 0
    if no_bc:
        p.block_compression = 0
    o.done()
    return _run_shape("pca", o, p, model, out_dir, progress)


def _screens(o: _Options, cmd: str, screens):
    """--screens: presets, "WxH" or "WxH@PPD" (a list or "a,b"), parsed by
    the library; the array and its count."""
    from . import _check
    names = [x for x in (screens.split(",") if isinstance(screens, str) else screens) if x]
    if not names or len(names) > 16:
        o._bad(f"{cmd}: --screens: '{screens}' names no screen" if not names else
               f"{cmd}: --screens: at most 16 screens")
    scr = o.array("jnd_poi_screen", len(names))
    for i, name in enumerate(names):
        _check(lib.jnd_poi_screen_parse(str(name).encode(), scr + i), f"{cmd}: --screens: ")
    return scr, len(names)


def _char_array(o: _Options, strings: list):
    return o.array("const char *", strings + [ffi.NULL])


def calibrate(thresholds_csv: PathLike, out_path: PathLike, *, pairs: Optional[PathLike] = None,
              sizes: IntList = None, folds: Optional[int] = None, p: Optional[float] = None,
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
    o.give(sizes=sizes, folds=folds, p=p, bias_range=bias_range)
    s = o.numbers("sizes", True, 64, 1, 32768)
    if s is not None:
        c.sizes, c.nsizes = o.array("int", s), len(s)
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
    return _run_shape("calibrate", o, c, thresholds_csv, out_path, progress)


def lod(model: PathLike, out_dir: PathLike, *, errors: Union[str, Sequence[float], None] = None,
        ratios: Union[str, Sequence[float], None] = None, level: Union[PathLike, Sequence[PathLike]] = (),
        rebuild: bool = False, lock_border: Optional[bool] = None, no_sloppy: bool = False,
        chain_only: bool = False, screens: Union[str, Sequence[str], None] = None,
        virtual_scale: Optional[float] = None, max_virtual: Optional[int] = None,
        surface_samples: Optional[int] = None, meshopt_pixels: Optional[float] = None,
        pixel_error: Optional[float] = None, no_textures: bool = False, judge_views: Optional[int] = None,
        far_coverage: Optional[float] = None, tolerance: Optional[float] = None, max_px: Optional[int] = None,
        no_pop: bool = False, pop_speed: Optional[float] = None, pop_motion: Optional[str] = None,
        no_perceptual: bool = False, progress: Progress = None, **options) -> TaskResult:
    """``jnd lod MODEL -o OUT_DIR``: a level-of-detail chain, 003's Point of
    Imperceptibility per screen and, per screen, the perceptual choice and
    each level's switch distance (docs/lod.md). model: a .gltf/.glb/.obj
    file or "builtin"; out_dir gets lod.json, model/NAME.glb (every level,
    MSFT_lod) and pareto_SCREEN.png. errors: error targets, fractions of the
    model's extent, rising ("1/1024,1/256" or numbers); ratios: triangle
    ratios instead, falling; level: levels from other files, finest first;
    lock_border: True/False for --lock-border/--no-lock-border (None: the
    library's choice); screens: presets, "WxH" or "WxH@PPD"; judge_views,
    far_coverage, tolerance, max_px, no_pop, pop_speed (°/s), pop_motion
    ("orbit", "spin" or "pan"), no_perceptual: the perceptual step. Views
    (views, seed, coverage, distance in object units, fov, lights, env,
    samples, anisotropy, platform, map_size (512)), criterion (p, q),
    threads and the common options as in the module's help. ``progress``
    gets the stage's name as its line on every step."""
    o = _Options("lod", options)
    p = ffi.new("jnd_lod_run_params *")
    lib.jnd_lod_run_defaults(p)
    # the shared view options, where lod has a use for them, into poi and sw
    vs = ffi.new("jnd_view_set *")
    vs.sampling.count, vs.sampling.seed, vs.sampling.coverage = p.poi.views, p.poi.seed, p.poi.coverage
    vs.sampling.distance, vs.sampling.fov_y_deg, vs.sampling.lights = p.sw.distance, p.poi.fov_y_deg, p.poi.lights
    vs.render.env_path, vs.render.anisotropy, vs.render.platform = p.poi.env_path, p.poi.anisotropy, p.poi.platform
    vs.render.samples = p.sw.judge.views.render.samples
    for name in ("size", "elevation", "light_intensity", "cameras"):
        if o.has(name):
            o._bad(f"lod: --{name.replace('_', '-')} is not an option of lod: its views are rendered at each "
                   "screen's size around the object; see jnd lod --help")
    map_size = o.views(vs, {"map_size": p.run.map_size})
    p.poi.views, p.poi.seed, p.poi.coverage = vs.sampling.count, vs.sampling.seed, vs.sampling.coverage
    p.poi.fov_y_deg, p.poi.lights = vs.sampling.fov_y_deg, vs.sampling.lights
    p.poi.env_path, p.poi.anisotropy, p.poi.platform = vs.render.env_path, vs.render.anisotropy, vs.render.platform
    p.sw.distance, p.sw.judge.views.render.samples = vs.sampling.distance, vs.render.samples
    o.criterion(p.sw.judge.criterion)
    n = o.threads(p)
    if n is not None:
        p.chain.threads = n
    o.run_options(p.run, map_size)
    o.give(errors=errors, ratios=ratios, virtual_scale=virtual_scale, max_virtual=max_virtual,
                surface_samples=surface_samples, meshopt_pixels=meshopt_pixels, pixel_error=pixel_error,
                judge_views=judge_views, far_coverage=far_coverage, tolerance=tolerance, max_px=max_px,
                pop_speed=pop_speed, pop_motion=pop_motion)
    if errors is not None and ratios is not None:
        o._bad("lod: give --errors or --ratios, not both")
    e = o.numbers("errors", False, 63, 1e-6, 1)   # the command's range: the chain takes what it is given
    if e is not None:
        p.chain.errors, p.chain.nerrors = o.array("double", e), len(e)
    r = o.numbers("ratios", False, 63, 0, 1)
    if r is not None:
        p.chain.ratios, p.chain.nratios = o.array("double", r), len(r)
    levels = [os.fspath(level)] if isinstance(level, (str, os.PathLike)) else [os.fspath(x) for x in level]
    if len(levels) > 63:
        o._bad("lod: at most 63 --level files")
    p.level_paths, p.nlevel_paths = _char_array(o, [o.cstr(x) for x in levels]), len(levels)
    p.rebuild = 1 if rebuild else 0
    if lock_border is not None:
        p.chain.lock_border = 1 if lock_border else 0
    if no_sloppy:
        p.chain.allow_sloppy = 0
    if chain_only:
        p.analyse = 0
    if screens is not None:
        p.poi.screens, p.poi.nscreens = _screens(o, "lod", screens)
    # the library checks each of these (lod: ... outside ...)
    for name, target, field, integer in (
            ("virtual_scale", p.poi, "virtual_scale", False), ("max_virtual", p.poi, "max_virtual_px", True),
            ("surface_samples", p.poi, "surface_samples", True), ("meshopt_pixels", p.poi, "meshopt_pixels", False),
            ("pixel_error", p.poi, "pixel_error", False), ("judge_views", p.sw.judge.views.sampling, "count", True),
            ("far_coverage", p.sw, "far_coverage", False), ("tolerance", p.sw, "tolerance", False),
            ("max_px", p.sw, "max_px", True), ("pop_speed", p.sw, "pop_speed", False)):
        x = o.number(name, integer=integer)
        if x is not None:
            setattr(target, field, x)
    if no_textures:
        p.poi.textures = 0
    if no_pop:
        p.sw.pop = 0
    m = o.choice("pop_motion", {"orbit": lib.JND_POP_ORBIT, "spin": lib.JND_POP_OBJECT, "pan": lib.JND_POP_PAN})
    if m is not None:
        p.sw.pop_motion = m
    if no_perceptual:
        p.perceptual = 0
    o.done()
    return _run_shape("lod", o, p, model, out_dir, progress)


_RENDER_OUTPUTS = {"color": "JND_RENDER_COLOR", "colour": "JND_RENDER_COLOR", "depth": "JND_RENDER_DEPTH",
                   "mask": "JND_RENDER_MASK", "motion": "JND_RENDER_MOTION", "mip": "JND_RENDER_MIP",
                   "exr": "JND_RENDER_EXR"}


def render(model: PathLike, out_dir: PathLike, *, lod: Optional[int] = None, strict: bool = False,
           outputs: Union[str, Sequence[str], None] = None, scale: Union[str, Sequence[str]] = (),
           replace: Union[str, Sequence[str]] = (), env_intensity: Optional[float] = None,
           env_rotation: Optional[float] = None, exposure: Optional[float] = None,
           background: Optional[str] = None, motion_orbit: Optional[float] = None, progress: Progress = None,
           **options) -> TaskResult:
    """``jnd render MODEL -o OUT_DIR``: frames of an asset under the views
    (docs/render.md). out_dir gets view_NNN*.png (and .exr) and views.json.
    lod: the level rendered; strict: a warning about the asset is an error;
    outputs: of color, depth, mask, motion, mip, exr; scale: "MAP=FACTOR" or
    "MAP=WxH" edits, replace: "MAP=FILE" edits (applied scales first, then
    replacements, each in its order); env_intensity, env_rotation (°),
    exposure, background ("black" or "env"), motion_orbit (°). Views (512²
    by default) and the common options as in the module's help; fixed
    lights (--light) are the command's only."""
    from . import JndError
    o = _Options("render", options)
    p = ffi.new("jnd_render_params *")
    lib.jnd_render_defaults(p)
    p.views.render.width = p.views.render.height = 512
    map_size = o.views(p.views)
    o.run_options(p.run, map_size)
    o.give(lod=lod, env_intensity=env_intensity, env_rotation=env_rotation, exposure=exposure,
                motion_orbit=motion_orbit, background=background)
    for name, field, lo, hi, integer in (("lod", "lod", 0, 63, True), ("env_intensity", "env_intensity", 0, 1e6, False),
                                         ("env_rotation", "env_rotation_deg", -3600, 3600, False),
                                         ("exposure", "exposure", 0, 1e9, False),
                                         ("motion_orbit", "motion_orbit_deg", -180, 180, False)):
        x = o.number(name, lo, hi, integer)
        if x is not None:
            setattr(p, field, x)
    bg = o.choice("background", {"black": 0, "env": 1})
    if bg is not None:
        p.background_env = bg
    p.strict = 1 if strict else 0
    if outputs is not None:
        names = outputs.split(",") if isinstance(outputs, str) else list(outputs)
        if not names or any(x not in _RENDER_OUTPUTS for x in names):
            raise JndError(f"render: --outputs: '{outputs}' is not a list of color,depth,mask,motion,mip,exr")
        p.outputs = 0
        for x in names:
            p.outputs |= getattr(lib, _RENDER_OUTPUTS[x])
    edits = []
    for kind, specs in (("scale", scale), ("replace", replace)):
        for spec in [specs] if isinstance(specs, str) else specs:
            name, eq, value = str(spec).rpartition("=")
            if not eq or not name or not value or len(edits) >= 64:
                raise JndError(f"render: '{spec}' is not MAP=VALUE (at most 64 edits)")
            e = {"map": o.cstr(name), "file": ffi.NULL, "factor": 0.0, "w": 0, "h": 0}
            if kind == "replace":
                e["file"] = o.cstr(value)
            elif "x" in value:
                e["w"], e["h"] = o._size("scale", value, 1, 32768)
            else:
                o.give(scale=value)
                e["factor"] = o.number("scale", 1e-6, 16)
            edits.append(e)
    if edits:
        p.edits, p.nedits = o.array("jnd_map_edit", edits), len(edits)
    o.done()
    return _run_shape("render", o, p, model, out_dir, progress)


def diff_run(ref: PathLike, test: PathLike, *, map: Optional[PathLike] = None,
             heatmap: Optional[PathLike] = None, heatmap_max: Optional[float] = None,
             fail_above: Optional[float] = None, pool: Optional[str] = None,
             calibration: Optional[PathLike] = None, motion: Optional[PathLike] = None,
             fps: Optional[float] = None, weights: Optional[PathLike] = None,
             gaze: Optional[Sequence[float]] = None, **options) -> TaskResult:
    """``jnd diff REF TEST``, the task: compares two image files on the
    display and writes what is asked, all or nothing and never over an input:
    map (the JND map, EXR), heatmap (PNG, its top heatmap_max JND), json (the
    report). pool ("p93", "max", ...), calibration (a ``jnd calibrate``
    file), motion (a 2-channel map, pixels per frame, at fps), weights (a
    weight map), gaze ((x, y) pixels); display options and threads as in the
    module's help. The result's fields are the report's (``p_detect``,
    ``jnd_p93``, ...); ``passes`` is False where P exceeds fail_above (the
    command's exit status 1). For arrays, or many comparisons on one display,
    use :func:`jnd.diff` or :class:`jnd.Model`."""
    from . import _check
    o = _Options("diff", options)
    p = ffi.new("jnd_diff_params *")
    lib.jnd_diff_defaults(p)
    p.exr_scale_given = 1 if o.display(p.model) else 0
    o.run_options(p.run)
    o.give(heatmap_max=heatmap_max, fail_above=fail_above, fps=fps, gaze=gaze)
    for name, target, field, lo, hi in (("heatmap_max", p, "heatmap_max", 0.2, 1e4),
                                        ("fail_above", p, "fail_above", 0, 1), ("fps", p.model, "fps", 1, 1000)):
        x = o.number(name, lo, hi)
        if x is not None:
            setattr(target, field, x)
    g = o.pair("gaze")
    if g is not None:
        p.model.has_gaze, p.model.gaze_x, p.model.gaze_y = 1, g[0], g[1]
    if pool is not None:
        _check(lib.jnd_pooling_parse(str(pool).encode(), ffi.addressof(p.pool)), "diff: --pool: ")
    for value, field in ((map, "map_path"), (heatmap, "heatmap_path"), (calibration, "calibration_path"),
                         (motion, "motion_path"), (weights, "weights_path")):
        if value is not None:
            setattr(p, field, o.cstr(value))
    o.done()
    c_ref, c_test = o.cstr(ref), o.cstr(test)
    return _run("diff", o, lambda params, out: lib.jnd_diff_run(c_ref, c_test, params, out), lib.jnd_diff_result_free,
                p, None, fail_above is not None)


def csf(data: PathLike, out_csv: Optional[PathLike] = None, *, colors: Optional[PathLike] = None,
        backgrounds: Optional[PathLike] = None, dataset: Union[str, Sequence[str]] = (), static_only: bool = False,
        every: Optional[int] = None, fit: bool = False, cross_validate: bool = False,
        fit_only: Union[str, Sequence[str], None] = None, search_every: Optional[int] = None,
        iterations: Optional[int] = None, set: Union[str, dict, Sequence[str], None] = None,
        min_band: Optional[float] = None, progress: Progress = None, **options) -> TaskResult:
    """``jnd csf DATA.csv [-o OUT.csv]``: the vision model's contrast
    sensitivity for every stimulus of a castleCSF-format CSV against the
    measured one (docs/csf.md); the report's result holds the RMS errors in
    dB per data set and pooled. out_csv: also the rows with their
    predictions; colors, backgrounds: the colour directions and backgrounds
    (default: beside data); dataset: only these data sets (at most 16);
    static_only; every: every N-th row; fit: fit the model's constants
    first (maximum a posteriori); cross_validate: leave one data set out;
    fit_only: the constants to fit ("a,b" or names); search_every: fits
    search on every N-th row; iterations: of Levenberg-Marquardt; set:
    constants' values ({"sensitivity": 0.1} or "NAME=VALUE" strings, in
    order); min_band: the lowest band's peak, cycles/degree. Common options:
    json, timings, threads. ``progress`` gets the stage's name on every
    step."""
    o = _Options("csf", options)
    p = ffi.new("jnd_csf_run_params *")
    lib.jnd_csf_run_defaults(p)
    o.threads(p.options)
    o.run_options(p.run)
    o.give(every=every, search_every=search_every, iterations=iterations, min_band=min_band)
    for name, target, field, lo, hi in (("every", p, "every", 1, 1000000),
                                        ("search_every", p.options, "search_every", 1, 1000),
                                        ("iterations", p.options, "max_iterations", 0, 1000)):
        x = o.number(name, lo, hi, True)   # the library takes these as they come
        if x is not None:
            setattr(target, field, x)
    x = o.number("min_band", 0.02, 10)
    if x is not None:
        p.model.min_band_cpd = x
    for value, field in ((colors, "colors"), (backgrounds, "backgrounds")):
        if value is not None:
            setattr(p, field, o.cstr(value))
    names = [dataset] if isinstance(dataset, str) else list(dataset)
    if len(names) > 16:
        o._bad("csf: at most 16 --dataset options")
    if names:
        p.datasets, p.ndatasets = _char_array(o, [o.cstr(n) for n in names]), len(names)
    p.static_only = 1 if static_only else 0
    p.options.fit = 1 if fit else 0
    p.options.cross_validate = 1 if cross_validate else 0
    if fit_only is not None:
        mask = 0
        for name in (fit_only.split(",") if isinstance(fit_only, str) else fit_only):
            k = lib.jnd_model_constant_find(str(name).encode())
            if k < 0:
                o._bad(f"csf: --fit-only: no constant '{name}' (jnd csf --list-constants)")
            mask |= 1 << k
        p.options.fit_mask, p.options.fit_mask_set = mask, 1
    if set is not None:
        items = (list(set.items()) if isinstance(set, dict) else
                 [str(x).partition("=")[::2] for x in ([set] if isinstance(set, str) else set)])
        for name, value in items:
            name = str(name)
            if not name or (not isinstance(set, dict) and not str(value)):
                o._bad(f"csf: --set: expected NAME=VALUE, not '{name}={value}'")
            k = lib.jnd_model_constant_find(name.encode())
            if k < 0:
                o._bad(f"csf: --set: no constant '{name}' (jnd csf --list-constants)")
            try:
                x = float(value)
            except (TypeError, ValueError):
                x = None
            if x is None or not math.isfinite(x):
                o._bad(f"csf: --set {name}: '{value}' is not a number")
            from . import _check
            _check(lib.jnd_model_constant_set(ffi.addressof(p.model), k, x), "csf: --set: ")
    o.done()
    return _run_shape("csf", o, p, data, out_csv, progress, result="jnd_csf_run_result",
                      progress_at=[(p.options, "progress", "user", False)])


_GAZE_VIEWS = ("seed", "env", "samples", "anisotropy", "platform", "map_size")


def _gaze_views(o: _Options, cmd: str, why: str, target) -> int:
    """The view options gaze has a use for (seed, env, samples, anisotropy,
    platform, map_size) into target's seed and renderer; returns the
    built-in assets' map size (512)."""
    o.views_only(_GAZE_VIEWS, cmd, why)
    vs = ffi.new("jnd_view_set *")
    lib.jnd_view_set_defaults(vs)
    vs.sampling.seed, vs.render = target.seed, target.render
    map_size = o.views(vs, {"map_size": 512})
    target.seed = vs.sampling.seed
    r = target.render
    r.env_path, r.samples, r.anisotropy, r.platform = (vs.render.env_path, vs.render.samples, vs.render.anisotropy,
                                                       vs.render.platform)
    return map_size


def gaze(model: PathLike, out_dir: PathLike, *, distances: Union[str, Sequence[float], None] = None,
         eccentricities: Union[str, Sequence[float], None] = None, orientations: Optional[int] = None,
         threshold: Optional[float] = None, errors: Union[str, Sequence[float], None] = None,
         min_px: Optional[int] = None, max_px: Optional[int] = None, whole_near: bool = False,
         params: Union[PathLike, Sequence[PathLike]] = (), progress: Progress = None, **options) -> TaskResult:
    """``jnd gaze MODEL -o OUT_DIR``: 002's table L(distance, eccentricity)
    of the coarsest level an observer looking elsewhere does not notice
    (docs/gaze.md). out_dir gets gaze.json, gaze.csv (what an engine loads),
    gaze.png and, for a plain mesh, model/NAME.glb with the chain made.
    distances: metres from the eye, ascending; eccentricities: degrees from
    the gaze, ascending, 0..90; orientations: per distance (8); threshold:
    the 2AFC probability both models stay below (0.75); errors: a plain
    mesh's chain, error targets ("1/1024,1/256"); min_px, max_px: the
    rendering side (64, 192); whole_near: judge near objects whole at reduced
    ppd; params: fitted parameters (``jnd gaze fit``'s gaze_fit.json files).
    Views: only seed, env, samples, anisotropy, platform, map_size (512);
    display and common options (json, timings) as in the module's help; the
    library's threads are OpenMP's (OMP_NUM_THREADS; the table does not
    depend on them). ``progress`` gets (None, done, total) per step."""
    o = _Options("gaze", options)
    rp = ffi.new("jnd_gaze_run_params *")
    lib.jnd_gaze_run_defaults(rp)
    t = rp.table
    map_size = _gaze_views(o, "gaze", "its views are --distances x --orientations, each at its own size; "
                           "see jnd gaze --help", t)
    o.display(t.measure.model, set_threads=False)
    o.run_options(rp.run, map_size)
    o.give(distances=distances, eccentricities=eccentricities, orientations=orientations, threshold=threshold,
           errors=errors, min_px=min_px, max_px=max_px)
    for name, count, field in (("distances", "ndistances", "distances_m"),
                               ("eccentricities", "neccentricities", "eccentricities_deg")):
        v = o.numbers(name, False, 256)   # the library checks the values (range, ascending)
        if v is not None:
            setattr(t, field, o.array("double", v))
            setattr(t, count, len(v))
    for name in ("orientations", "min_px", "max_px"):   # the library checks each
        x = o.number(name, integer=True)
        if x is not None:
            setattr(t, name, x)
    x = o.number("threshold")
    if x is not None:
        t.threshold = x
    t.chain = o.chain()
    if whole_near:
        t.near_window = 0
    files = [params] if isinstance(params, (str, os.PathLike)) else list(params)
    if len(files) > 8:
        o._bad("--params: at most 8 files")
    if files:
        rp.model_files, rp.nmodel_files = _char_array(o, [o.cstr(f) for f in files]), len(files)
    o.done()
    return _run_shape("gaze", o, rp, model, out_dir, progress, result="jnd_gaze_run_result",
                      progress_at=[(t, "progress", "progress_user", True)])


def gaze_fit(data: PathLike, out_dir: Optional[PathLike] = None, *, folds: Optional[int] = None,
             seed: Optional[int] = None, confidence: Optional[float] = None, b: Optional[float] = None,
             **options) -> TaskResult:
    """``jnd gaze fit DATA.csv [-o OUT_DIR]``: fits 002's spatial model
    (columns xor_deg, v_jnd, eccentricity_deg, seen) or its temporal model
    (t_jnd, seen) to observers' answers by maximum likelihood, with
    intervals and k-fold cross-validation (docs/gaze.md "Fitting"). out_dir:
    also OUT_DIR/gaze_fit.json (what ``jnd.gaze(params=...)`` reads); folds
    (4), seed (1), confidence (0.95), b: the weight's floor, fixed (2).
    Common options: json, timings."""
    o = _Options("gaze fit", options)
    rp = ffi.new("jnd_gaze_run_params *")
    lib.jnd_gaze_run_defaults(rp)
    rp.mode = lib.JND_GAZE_RUN_FIT
    f = rp.fit
    o.run_options(rp.run, 512)
    o.give(folds=folds, seed=seed, confidence=confidence, b=b)
    x = o.number("folds", integer=True)   # the library checks folds and confidence
    if x is not None:
        f.folds = x
    x = o.number("seed", 0, 9007199254740992.0)
    if x is not None:
        f.seed = int(x)
    x = o.number("confidence")
    if x is not None:
        f.confidence = x
    x = o.number("b", 1e-6, 1e6)
    if x is not None:
        f.start.b = x
    o.done()
    return _run_shape("gaze", o, rp, data, out_dir, None, result="jnd_gaze_run_result", progress_at=[])


def gaze_observers(models: Union[PathLike, Sequence[PathLike]], out_dir: PathLike, *,
                   sizes: Union[str, Sequence[float], None] = None,
                   eccentricities: Union[str, Sequence[float], None] = None, orientations: Optional[int] = None,
                   answers: Optional[int] = None, errors: Union[str, Sequence[float], None] = None,
                   min_px: Optional[int] = None, max_px: Optional[int] = None, progress: Progress = None,
                   **options) -> TaskResult:
    """``jnd gaze observers MODEL... -o OUT_DIR``: synthetic observers for
    ``gaze_fit`` (docs/gaze.md "Defaults"): out_dir gets spatial.csv,
    temporal.csv (one row per answer) and observers.json. sizes: the
    object's angular diameter, degrees; eccentricities: degrees, ascending;
    orientations (2); answers: Bernoulli answers per stimulus (40); errors:
    a plain mesh's chain; min_px, max_px (64, 192). Views: only seed, env,
    samples, anisotropy, platform, map_size (512); common options (json,
    timings). ``progress`` gets (None, done, total) per step."""
    o = _Options("gaze observers", options)
    rp = ffi.new("jnd_gaze_run_params *")
    lib.jnd_gaze_run_defaults(rp)
    rp.mode = lib.JND_GAZE_RUN_OBSERVERS
    ob = rp.observers
    map_size = _gaze_views(o, "gaze observers", "its views are --sizes x --orientations; "
                           "see jnd gaze observers --help", ob)
    o.run_options(rp.run, map_size)
    o.give(sizes=sizes, eccentricities=eccentricities, orientations=orientations, answers=answers, errors=errors,
           min_px=min_px, max_px=max_px)
    for name, count, field in (("sizes", "nsizes", "sizes_deg"),
                               ("eccentricities", "neccentricities", "eccentricities_deg")):
        v = o.numbers(name, False, 64)   # the library checks the values
        if v is not None:
            setattr(ob, field, o.array("double", v))
            setattr(ob, count, len(v))
    for name in ("orientations", "answers", "min_px", "max_px"):   # the library checks each
        x = o.number(name, integer=True)
        if x is not None:
            setattr(ob, name, x)
    ob.chain = o.chain()
    files = [models] if isinstance(models, (str, os.PathLike)) else list(models)
    if len(files) > 64:
        o._bad("gaze observers: at most 64 models")
    rp.models, rp.nmodels = _char_array(o, [o.cstr(f) for f in files]), len(files)
    o.done()
    return _run_shape("gaze", o, rp, None, out_dir, progress, result="jnd_gaze_run_result",
                      progress_at=[(ob, "progress", "progress_user", True)])


def _pop_common(o: _Options, rp, fps, maps, max_regions, fail_above):
    """What both forms of pop share: the display, fps, threads, outputs."""
    o.display(rp.model, set_threads=False)
    n = o.threads(rp.model)
    if n is not None:
        rp.pop.threads = n
    o.give(fps=fps, max_regions=max_regions, fail_above=fail_above)
    for name, target, field, lo, hi, integer in (("fps", rp.model, "fps", 1, 1000, False),
                                                 ("max_regions", rp, "max_regions", 0, 1 << 30, True),
                                                 ("fail_above", rp, "fail_above", -100, 100, False)):
        x = o.number(name, lo, hi, integer)   # the library takes these as they come
        if x is not None:
            setattr(target, field, x)
    rp.maps = 1 if maps else 0
    return n


def pop(model: PathLike, out_dir: PathLike, *, switch: Optional[int] = None, frame: Optional[int] = None,
        orbit: Optional[float] = None, translate: Optional[float] = None, spin: Optional[float] = None,
        pan: Optional[float] = None, direction: Optional[Sequence[float]] = None, unit_m: Optional[float] = None,
        level: Union[PathLike, Sequence[PathLike]] = (), errors: Union[str, Sequence[float], None] = None,
        rebuild: bool = False, decide: bool = False, speeds: Union[str, Sequence[float], None] = None,
        tolerance: Optional[float] = None, coverage_range: Optional[Sequence[float]] = None,
        fps: Optional[float] = None, maps: bool = False, max_regions: Optional[int] = None,
        fail_above: Optional[float] = None, progress: Progress = None, **options) -> TaskResult:
    """``jnd pop MODEL -o OUT_DIR``, the asset form: will the switch from
    level ``switch`` to the next pop (004 §3.2; docs/pop.md)? jnd renders
    the switch from the first view at frame ``frame`` of the motion — one of
    orbit (°/s, the camera circles), translate (m/s along direction, the
    camera's x right, y up, z back), spin (°/s, the object turns), pan (°/s,
    the camera turns in place); unit_m: metres per object unit. The chain is
    the file's MSFT_lod levels, the ``level`` files, or one made (errors;
    rebuild: even when the file has levels). decide (or speeds, °/s): the
    popping-free switch distance of every level and speed (tolerance,
    coverage_range (near, far)). out_dir gets pop.json, regions.png (and
    switch.png; with maps, jnd.exr and weights.exr). fps (60), max_regions
    (100), fail_above: ``passes`` is False when the largest rating exceeds
    it. Views (512², map_size 2048), display and common options as in the
    module's help. ``progress`` gets the stage's name on every step."""
    from . import JndError
    o = _Options("pop", options)
    rp = ffi.new("jnd_pop_run_params *")
    lib.jnd_pop_run_defaults(rp)
    a = rp.asset
    vs = ffi.new("jnd_view_set *")
    lib.jnd_view_set_defaults(vs)
    vs.render.width = vs.render.height = 512
    cameras = o.kw.get("cameras")
    map_size = o.views(vs)
    n = _pop_common(o, rp, fps, maps, max_regions, fail_above)
    o.run_options(rp.run, map_size)
    motions = [(k, v) for k, v in (("orbit", orbit), ("translate", translate), ("spin", spin), ("pan", pan))
               if v is not None]
    if len(motions) > 1:
        raise JndError("pop: give one of --orbit, --translate and --spin")
    if errors is not None and level:
        raise JndError("pop: give --errors or --level files, not both")
    o.give(switch=switch, frame=frame, unit_m=unit_m, tolerance=tolerance, **dict(motions))
    for name, target, field, lo, hi, integer in (("switch", a, "level", 0, 62, True),
                                                 ("frame", a, "frame", -100000, 100000, True),
                                                 ("unit_m", a.motion, "unit_m", 1e-9, 1e9, False),
                                                 ("tolerance", a.search, "tolerance", 1e-4, 10, False)):
        x = o.number(name, lo, hi, integer)   # the command's ranges: the library takes these as they come
        if x is not None:
            setattr(target, field, x)
    if motions:
        kind, _ = motions[0]
        a.motion.kind = {"orbit": lib.JND_POP_ORBIT, "translate": lib.JND_POP_TRANSLATE, "spin": lib.JND_POP_OBJECT,
                         "pan": lib.JND_POP_PAN}[kind]
        a.motion.speed = o.number(kind, -100000, 100000)
    if direction is not None:
        o.give(direction=direction)
        d = o.numbers("direction", False, 3)
        if len(d) != 3 or not any(d):
            raise JndError(f"pop: --direction: '{direction}' is not X,Y,Z (not all 0)")
        a.motion.direction = d
    if coverage_range is not None:
        o.give(coverage_range=coverage_range)
        near, far = o.pair("coverage_range")
        if not (near <= 10 and near > far and far >= 0.001):
            raise JndError(f"pop: --coverage-range: '{coverage_range}' is not N,F with 10 >= N > F >= 0.001")
        a.search.coverage_near, a.search.coverage_far = near, far
    o.give(errors=errors)
    chain = o.chain()
    if chain != ffi.NULL:
        a.chain.errors, a.chain.nerrors = chain.errors, chain.nerrors
    a.rebuild = 1 if rebuild else 0
    if decide:
        a.decide = 1
    if speeds is not None:
        o.give(speeds=speeds)
        sp = o.numbers("speeds", False, 64, -100000, 100000)
        a.speeds, a.nspeeds, a.decide = o.array("double", sp), len(sp), 1
    levels = [level] if isinstance(level, (str, os.PathLike)) else list(level)
    if len(levels) > 63:
        raise JndError("pop: at most 63 --level files")
    a.views = vs[0]
    a.cameras = vs.cameras_path if cameras is not None else ffi.NULL
    a.builtin_map_size = map_size
    a.level_paths, a.nlevel_paths = _char_array(o, [o.cstr(x) for x in levels]), len(levels)
    if n is not None:
        a.chain.threads = n
    o.done()
    return _run_shape("pop", o, rp, model, out_dir, progress, has_passes=fail_above is not None,
                      result="jnd_pop_run_result")


def pop_frames(new: PathLike, expected: PathLike, out_dir: PathLike, *, displacement: Optional[PathLike] = None,
               displacement_expected: Optional[PathLike] = None, weights: Optional[PathLike] = None,
               depth: Optional[PathLike] = None, depth_expected: Optional[PathLike] = None,
               prev_depth: Optional[PathLike] = None, prev_depth_expected: Optional[PathLike] = None,
               prev_frame: Optional[PathLike] = None, prev_shading: Optional[PathLike] = None,
               mask: Optional[PathLike] = None, frames: Optional[Sequence[int]] = None, fps: Optional[float] = None,
               maps: bool = False, max_regions: Optional[int] = None, fail_above: Optional[float] = None,
               progress: Progress = None, **options) -> TaskResult:
    """``jnd pop NEW EXPECTED -o OUT_DIR``, the frame form: NEW is the frame
    where the switch happens, rendered with the new level, EXPECTED the
    same frame with the previous level (004 §3.2, §4; docs/pop.md). Frames:
    PNG/JPEG (sRGB) or EXR/HDR (linear, cd/m² × exr_scale); displacement
    (and displacement_expected): screen displacement from the previous
    frame, pixels (EXR, 2 channels); weights, depth, depth_expected,
    prev_depth, prev_depth_expected, prev_frame, prev_shading, mask: as the
    command's options. frames: (first, last): a sequence, the paths holding
    %d or %0Nd. fps (60), maps, max_regions (100), fail_above: ``passes``
    is False when the largest rating exceeds it. Display and common options
    as in the module's help."""
    from . import JndError
    o = _Options("pop", options)
    rp = ffi.new("jnd_pop_run_params *")
    lib.jnd_pop_run_defaults(rp)
    _pop_common(o, rp, fps, maps, max_regions, fail_above)
    o.run_options(rp.run, 2048)
    f = rp.frames
    for value, field in ((new, "actual"), (expected, "expected"), (displacement, "displacement"),
                         (displacement_expected, "displacement_expected"), (weights, "weights"), (depth, "depth"),
                         (depth_expected, "depth_expected"), (prev_depth, "prev_depth"),
                         (prev_depth_expected, "prev_depth_expected"), (prev_frame, "prev_color"),
                         (prev_shading, "prev_shading"), (mask, "mask")):
        if value is not None:
            setattr(f, field, o.cstr(value))
    if frames is not None:
        o.give(frames=frames)
        fr = o.numbers("frames", True, 2, 0, 1 << 30)
        if len(fr) != 2 or fr[1] < fr[0]:
            raise JndError(f"pop: --frames: '{frames}' is not FIRST,LAST with 0 <= FIRST <= LAST")
        rp.seq.first, rp.seq.last, rp.sequence = fr[0], fr[1], 1
    o.done()
    return _run_shape("pop", o, rp, None, out_dir, progress, has_passes=fail_above is not None,
                      result="jnd_pop_run_result")


_SIZE_UNITS = {"": 1, "B": 1, "KiB": 1024, "MiB": 1048576, "GiB": 1073741824, "kB": 1e3, "KB": 1e3, "MB": 1e6,
               "GB": 1e9}


def budget(model: PathLike, out_dir: PathLike, *, memory: Union[str, float, None] = None,
           triangles: Optional[int] = None, bytes_per_triangle: Optional[float] = None,
           verify_views: Optional[int] = None, margin: Optional[float] = None, confirm: Optional[int] = None,
           min_size: Optional[int] = None, screens: Union[str, Sequence[str], None] = None,
           errors: Union[str, Sequence[float], None] = None, judge_views: Optional[int] = None,
           far_coverage: Optional[float] = None, tolerance: Optional[float] = None, max_px: Optional[int] = None,
           no_pop: bool = False, progress: Progress = None, **options) -> TaskResult:
    """``jnd budget MODEL -o OUT_DIR``: the texture sizes and the levels of
    detail chosen together under one cost, the textures' GPU memory plus the
    finest level's triangles at an exchange rate (docs/budget.md). out_dir
    gets budget.json, model/NAME.glb (the chosen levels, maps at the chosen
    sizes) and pareto.png. Without a budget: the cheapest choice nobody
    notices; memory ("8MiB", "512KB" or bytes) and/or triangles: the least
    noticed choice within them. bytes_per_triangle: the exchange rate (0:
    level 0's own); verify_views: held-out views at each coarser level's
    switch distance (4); margin, confirm, min_size: texres's search;
    screens, errors, judge_views, far_coverage, tolerance, max_px, no_pop:
    lod's. Views, display, criterion (p, q, pool, calibration) and common
    options as in the module's help. ``passes`` is False where the choice
    fails the criterion (the command's exit status 1); ``progress`` gets
    each stage's line."""
    from . import JndError
    o = _Options("budget", options)
    p = ffi.new("jnd_budget_params *")
    lib.jnd_budget_defaults(p)
    vs = ffi.new("jnd_view_set *")   # the command's views: the defaults, texres's size, lod's coverage
    lib.jnd_view_set_defaults(vs)
    vs.render.width, vs.render.height = p.texres.judge.views.render.width, p.texres.judge.views.render.height
    vs.sampling.coverage = p.lod.poi.coverage
    map_size = o.views(vs, {"map_size": p.run.map_size})
    o.display(p.texres.judge.model, set_threads=False)
    n = o.threads(p.texres.judge.model)
    o.criterion(p.texres.judge.criterion)
    o.calibration(p.texres.judge)
    o.run_options(p.run, map_size)
    p.texres.judge.views = vs[0]
    p.lod.poi.coverage, p.lod.poi.seed = vs.sampling.coverage, vs.sampling.seed
    p.lod.poi.fov_y_deg, p.lod.poi.lights = vs.sampling.fov_y_deg, vs.sampling.lights
    p.lod.poi.env_path, p.lod.poi.platform = vs.render.env_path, vs.render.platform
    p.lod.sw.judge.criterion, p.lod.sw.judge.calibration = p.texres.judge.criterion, p.texres.judge.calibration
    if n is not None:
        p.lod.threads = n
    if memory is not None:
        m = None
        if isinstance(memory, (int, float)) and not isinstance(memory, bool):
            m = float(memory)
        else:
            text = str(memory).strip()
            num = text.rstrip("BKiMGkb ")
            unit = text[len(num):].strip()
            try:
                if unit in _SIZE_UNITS:
                    m = float(num) * _SIZE_UNITS[unit]
            except ValueError:
                m = None
        if m is None or not math.isfinite(m) or not m > 0:
            raise JndError(f"budget: --memory: '{memory}' is not a size above 0 (e.g. 8MiB; units B, KiB, MiB, GiB, "
                           "kB, MB, GB)")
        p.memory_bytes = m
    o.give(triangles=triangles, bytes_per_triangle=bytes_per_triangle, verify_views=verify_views, margin=margin,
           confirm=confirm, min_size=min_size, judge_views=judge_views, far_coverage=far_coverage,
           tolerance=tolerance, max_px=max_px)
    # the library checks the budget, the rate, the held-out views and texres's and lod's fields
    for name, target, field, integer in (
            ("triangles", p, "triangles", True), ("bytes_per_triangle", p, "bytes_per_triangle", False),
            ("verify_views", p, "verify_views", True), ("margin", p.texres, "margin", False),
            ("confirm", p.texres, "confirm_rounds", True), ("min_size", p.texres, "min_size", True),
            ("judge_views", p.lod.sw.judge.views.sampling, "count", True),
            ("far_coverage", p.lod.sw, "far_coverage", False), ("tolerance", p.lod.sw, "tolerance", False),
            ("max_px", p.lod.sw, "max_px", True)):
        x = o.number(name, integer=integer)
        if x is not None:
            setattr(target, field, x)
    if screens is not None:
        p.lod.poi.screens, p.lod.poi.nscreens = _screens(o, "budget", screens)
    o.give(errors=errors)
    chain = o.chain()
    if chain != ffi.NULL:
        p.lod.chain.errors, p.lod.chain.nerrors = chain.errors, chain.nerrors
    if no_pop:
        p.lod.sw.pop = 0
    o.done()
    return _run_shape("budget", o, p, model, out_dir, progress, has_passes=True)
