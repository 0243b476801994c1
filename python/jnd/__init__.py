"""jnd: what is the cheapest asset nobody will notice?

A binding of libjnd's C API (include/jnd.h): the same model, the same
numbers as the ``jnd`` command. Images go in and out as NumPy arrays.

    import jnd
    r = jnd.diff("ref.png", "test.png", display="standard-4k")
    print(r.p_detect, r.jnd_max)          # probability a viewer notices; JND
    heat = r.jnd_map                      # float32 H x W, in JND (1 = one JND)

Arrays: H x W (grey) or H x W x C with C = 1..4 (grey, grey+alpha, RGB,
RGBA). ``encoding="srgb"``: display signal, float in 0..1, or uint8/uint16
scaled by 255/65535 (as PNG/JPEG files); ``encoding="linear"``: linear light,
multiplied by the display's ``exr_scale`` to give cd/m² (as EXR files).
Alpha is composited over the display's black. Errors raise :class:`JndError`
with libjnd's one-line message. Calls into the library release the GIL.
"""
from __future__ import annotations

import dataclasses
import os
import threading
from typing import Optional, Sequence, Tuple, Union

import numpy as np

from ._jnd_cffi import ffi, lib

__all__ = [
    "JndError", "Display", "DiffResult", "Model", "diff", "display", "display_presets",
    "ppd_from_geometry", "probability", "read_image", "version",
]

ImageLike = Union[str, os.PathLike, np.ndarray]


class JndError(Exception):
    """An error from libjnd: ``str(e)`` is its one-line message ("FILE: what is
    wrong" where a file is involved), ``e.status`` the jnd_status name."""

    def __init__(self, message: str, status: str = "JND_ERR_ARG"):
        super().__init__(message)
        self.status = status


_STATUS = {getattr(lib, n): n for n in dir(lib) if n.startswith("JND_ERR_")}


def _check(status: int, prefix: str = "") -> None:
    if status != lib.JND_OK:
        raise JndError(prefix + ffi.string(lib.jnd_last_error()).decode("utf-8", "replace"),
                       _STATUS.get(status, str(status)))


def version() -> str:
    """The library's version, "MAJOR.MINOR.PATCH"."""
    return ffi.string(lib.jnd_version()).decode()


# ---------------------------------------------------------------- display --

@dataclasses.dataclass
class Display:
    """How a screen shows an image (jnd_display): its ppd sets which spatial
    frequencies the model sees; luminances are in cd/m², illuminance in lux."""

    name: str = "standard-fhd"
    ppd: float = 0.0            # pixels per degree of visual angle at the screen centre
    peak_cdm2: float = 0.0      # luminance of full white, cd/m²
    black_cdm2: float = 0.0     # luminance the display emits for black, cd/m²
    ambient_lux: float = 0.0    # illuminance of the room on the screen, lux
    reflectivity: float = 0.0   # fraction of ambient light the screen reflects
    exr_scale: float = 1.0      # linear inputs: cd/m² per unit value
    diagonal_in: float = 0.0    # geometry the ppd came from (0 where ppd was given)
    distance_m: float = 0.0
    width_px: int = 0
    height_px: int = 0
    task: str = "side-by-side"  # how the viewer compares the two images: "side-by-side" or "flicker"
                                # (toggled in place: stricter; docs/model.md "Viewing task")

    def _to_c(self):
        """The jnd_display. The library checks every quantity where a
        display is accepted (jnd_display_check: the model; the display's
        transform), with its one-line message ("display phone: ...")."""
        d = ffi.new("jnd_display *")
        name = self.name.encode()[:31]
        ffi.memmove(d.name, name, len(name))
        for f in dataclasses.fields(self):
            if f.name not in ("name", "task"):
                setattr(d, f.name, getattr(self, f.name))
        task = ffi.new("jnd_viewing_task *")
        _check(lib.jnd_viewing_task_parse(str(self.task).encode(), task), f"display {self.name}: task: ")
        d.task = task[0]
        return d

    @classmethod
    def _from_c(cls, d) -> "Display":
        kw = {f.name: getattr(d, f.name) for f in dataclasses.fields(cls) if f.name not in ("name", "task")}
        return cls(name=ffi.string(d.name).decode(), task=ffi.string(lib.jnd_viewing_task_name(d.task)).decode(),
                   **kw)


def display_presets() -> list:
    """The names of the display presets (standard-fhd, standard-4k, phone, ...)."""
    names, p, i = [], lib.jnd_display_preset_names(), 0
    while p[i] != ffi.NULL:
        names.append(ffi.string(p[i]).decode())
        i += 1
    return names


def display(name: str = "standard-fhd", **overrides) -> Display:
    """A display preset by name, with any field overridden by keyword
    (``jnd.display("phone", peak_cdm2=500)``)."""
    d = ffi.new("jnd_display *")
    _check(lib.jnd_display_preset(name.encode(), d))
    out = Display._from_c(d)
    for k, v in overrides.items():
        if not hasattr(out, k):
            raise JndError(f"display: no field {k!r}")
        setattr(out, k, v)
    return out


def ppd_from_geometry(diagonal_in: float, width_px: int, height_px: int, distance_m: float) -> float:
    """Pixels per degree at the centre of a flat screen of the given diagonal
    (inches) and resolution, seen from distance_m metres."""
    return lib.jnd_ppd_from_geometry(diagonal_in, width_px, height_px, distance_m)


def probability(jnd_value: float, beta: float = 3.5) -> float:
    """Probability of detection of a difference of jnd_value JND (000 eq. 4)."""
    return lib.jnd_probability(jnd_value, beta)


# ----------------------------------------------------------------- images --

def _image_from_array(a: np.ndarray, encoding: str, what: str):
    """A library-owned jnd_image (planar float32) and its jnd_image_info."""
    if not isinstance(a, np.ndarray):
        raise JndError(f"{what}: expected a NumPy array or a file path, got {type(a).__name__}")
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or not 1 <= a.shape[2] <= 4 or a.shape[0] < 1 or a.shape[1] < 1:
        raise JndError(f"{what}: expected an H x W or H x W x C array with C = 1..4, got shape {a.shape}")
    if encoding not in ("srgb", "linear"):
        raise JndError(f"{what}: encoding must be 'srgb' or 'linear', not {encoding!r}")
    if a.dtype == np.uint8:
        planar = a.astype(np.float32) / np.float32(255)
    elif a.dtype == np.uint16:
        planar = a.astype(np.float32) / np.float32(65535)
    elif a.dtype in (np.float32, np.float64, np.float16):
        planar = a.astype(np.float32, copy=False)
    else:
        raise JndError(f"{what}: unsupported dtype {a.dtype} (float32/64/16, uint8 or uint16)")
    if not np.isfinite(planar).all():
        raise JndError(f"{what}: the image has NaN or Inf values")
    if (planar < 0).any():
        raise JndError(f"{what}: the image has negative values")
    planar = np.ascontiguousarray(np.transpose(planar, (2, 0, 1)))
    h, w, c = a.shape
    img = ffi.new("jnd_image *")
    _check(lib.jnd_image_alloc(img, w, h, c))
    ffi.memmove(img.data, ffi.from_buffer(planar), planar.nbytes)
    info = ffi.new("jnd_image_info *")
    info.encoding = lib.JND_ENCODING_SRGB if encoding == "srgb" else lib.JND_ENCODING_LINEAR
    info.channels = c
    info.has_alpha = 1 if c in (2, 4) else 0
    info.bits = 8 if a.dtype == np.uint8 else 16 if a.dtype == np.uint16 else 32
    ffi.memmove(info.format, b"array", 5)
    return img, info


def _image_from_file(path, what: str):
    img = ffi.new("jnd_image *")
    info = ffi.new("jnd_image_info *")
    _check(lib.jnd_image_read(os.fsencode(path), img, info))
    return img, info


def _load(x: ImageLike, encoding: str, what: str):
    if isinstance(x, (str, os.PathLike)):
        return _image_from_file(x, what)
    return _image_from_array(x, encoding, what)


def _array_of(img) -> np.ndarray:
    """A copy of a jnd_image as H x W (one channel) or H x W x C float32."""
    n = img.w * img.h * img.c
    a = np.frombuffer(ffi.buffer(img.data, 4 * n), dtype=np.float32).reshape(img.c, img.h, img.w)
    a = np.transpose(a, (1, 2, 0)).copy()
    return a[:, :, 0] if img.c == 1 else a


def read_image(path: Union[str, os.PathLike]) -> Tuple[np.ndarray, str]:
    """Reads PNG, JPEG, Radiance HDR or OpenEXR as libjnd does: returns the
    pixels (float32, H x W x C; PNG/JPEG scaled to 0..1, still sRGB-encoded;
    HDR/EXR as stored) and their encoding, "srgb" or "linear"."""
    img, info = _image_from_file(path, str(path))
    try:
        a = _array_of(img)
    finally:
        lib.jnd_image_free(img)
    if a.ndim == 2:
        a = a[:, :, None]
    return a, "srgb" if info.encoding == lib.JND_ENCODING_SRGB else "linear"


# ------------------------------------------------------------------ model --

@dataclasses.dataclass
class DiffResult:
    """One comparison, as ``jnd diff`` reports it (its JSON "result")."""

    p_detect: float       # pooled probability of detection with the pooling asked for
    pooling: str          # that pooling: "p93", "pNN", "max", "mean" or "minkowski"
    p_p50: float
    p_p93: float
    p_p99: float
    p_max: float
    p_mean: float
    jnd_mean: float       # JND statistics of the map (1 = one just-noticeable difference)
    jnd_p93: float
    jnd_max: float
    jnd_minkowski: float  # Minkowski mean of the map, exponent 2.4
    width: int
    height: int
    bands_cpd: list       # peak frequency of each band of the model, cycles/degree, finest first
    jnd_map: np.ndarray   # float32 H x W, JND per pixel


class Model:
    """The vision model on one display, reusable for any number of
    comparisons (its CSF tables are built once). Thread-safe: concurrent
    calls on one Model are serialised; use one Model per thread to run them
    in parallel.

    display: a preset name or a :class:`Display`; gaze: a fixation point
    (x, y) in pixels, or None for foveal viewing everywhere; threads: the
    library's threads (0: OpenMP's default)."""

    def __init__(self, display: Union[str, Display] = "standard-fhd", *,
                 gaze: Optional[Sequence[float]] = None, threads: int = 0):
        d = globals()["display"](display) if isinstance(display, str) else display
        if not isinstance(d, Display):
            raise JndError(f"display: a preset name or a jnd.Display, not {type(display).__name__}")
        p = ffi.new("jnd_model_params *")
        lib.jnd_model_defaults(p)
        p.display = d._to_c()[0]
        if gaze is not None:
            if len(gaze) != 2:
                raise JndError("gaze: expected (x, y) in pixels")
            p.has_gaze, p.gaze_x, p.gaze_y = 1, float(gaze[0]), float(gaze[1])
        p.threads = int(threads)
        self.display = d
        self.beta = p.beta
        m = ffi.new("jnd_model **")
        _check(lib.jnd_model_create(p, m))
        self._m = ffi.gc(m[0], lib.jnd_model_free)
        self._lock = threading.Lock()

    def bands_cpd(self) -> list:
        """The peak frequency of each band, cycles/degree, finest first."""
        buf = ffi.new("double[32]")
        n = lib.jnd_model_band_peaks(self._m, buf, 32)
        return [round(buf[i] * 1e4) / 1e4 for i in range(min(n, 16))]

    def diff(self, ref: ImageLike, test: ImageLike, *, encoding: str = "srgb",
             pooling: str = "p93") -> DiffResult:
        """Compares test with ref as a viewer sees them on this display: the
        JND map (004 §3.1) and the probability that a viewer notices, pooled
        over the image (000 eq. 4, §6). ref, test: file paths or arrays (see
        the module's help); encoding applies to arrays."""
        pool = ffi.new("jnd_pooling *")
        _check(lib.jnd_pooling_parse(pooling.encode(), pool))
        ri, rinfo = _load(ref, encoding, "reference")
        try:
            ti, tinfo = _load(test, encoding, "test")
        except BaseException:
            lib.jnd_image_free(ri)
            raise
        out = ffi.new("jnd_image *")
        st = ffi.new("jnd_diff_stats *")
        w, h = ri.w, ri.h
        with self._lock:
            # jnd_diff_files consumes (frees) both images, on failure too
            status = lib.jnd_diff_files(self._m, ri, rinfo, ti, tinfo, ffi.NULL, pool, out, st)
        _check(status)
        try:
            jmap = _array_of(out)
        finally:
            lib.jnd_image_free(out)
        return DiffResult(p_detect=st.p_detect, pooling=pooling, p_p50=st.p_p50, p_p93=st.p_p93,
                          p_p99=st.p_p99, p_max=st.p_max, p_mean=st.p_mean, jnd_mean=st.jnd_mean,
                          jnd_p93=st.jnd_p93, jnd_max=st.jnd_max, jnd_minkowski=st.jnd_minkowski,
                          width=w, height=h, bands_cpd=self.bands_cpd(), jnd_map=jmap)


def diff(ref: ImageLike, test: ImageLike, display: Union[str, Display] = "standard-fhd", *,
         encoding: str = "srgb", pooling: str = "p93", gaze: Optional[Sequence[float]] = None,
         threads: int = 0) -> DiffResult:
    """``jnd diff`` as a call: see :meth:`Model.diff`. For many comparisons on
    one display, make a :class:`Model` once and call its diff."""
    return Model(display, gaze=gaze, threads=threads).diff(ref, test, encoding=encoding, pooling=pooling)


# ------------------------------------------------------------------ tasks --

from .tasks import (JndWarning, TaskResult, budget, calibrate, csf, diff_run, gaze, gaze_fit, gaze_observers,  # noqa: E402
                    lod, pca, pop, pop_frames, render, texres)

__all__ += ["JndWarning", "TaskResult", "budget", "calibrate", "csf", "diff_run", "gaze", "gaze_fit", "gaze_observers",
            "lod", "pca", "pop", "pop_frames", "render", "texres"]
