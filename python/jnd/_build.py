"""Builds jnd's C extension (cffi, API mode) against include/jnd.h and libjnd.so.

API mode, not ABI mode: the compiler checks every declaration below against
jnd.h, and structs declared with "..." take their layout from the header, so
the binding cannot drift from the library silently.

    python3 -m jnd._build --include DIR --libdir DIR --out DIR

writes DIR/jnd/_jnd_cffi*.so (the package's files are copied beside it).
The extension finds libjnd.so through an rpath to --libdir.
"""
import argparse
import os
import shutil
import sys

CDEF = r"""
typedef enum { JND_OK, JND_ERR_IO, JND_ERR_FORMAT, JND_ERR_ARG, JND_ERR_LIMIT,
               JND_ERR_NOMEM, JND_ERR_GL, JND_ERR_INTERNAL } jnd_status;
const char *jnd_last_error(void);
const char *jnd_version(void);

typedef struct { int w, h, c; float *data; } jnd_image;
jnd_status jnd_image_alloc(jnd_image *img, int w, int h, int c);
void jnd_image_free(jnd_image *img);

typedef enum { JND_ENCODING_SRGB, JND_ENCODING_LINEAR } jnd_encoding;
typedef struct {
  jnd_encoding encoding;
  int bits;
  int channels;
  int has_alpha;
  char format[8];
} jnd_image_info;
jnd_status jnd_image_read(const char *path, jnd_image *out, jnd_image_info *info);

typedef struct {
  char name[32];
  double ppd, peak_cdm2, black_cdm2, ambient_lux, reflectivity, exr_scale;
  double diagonal_in, distance_m;
  int width_px, height_px;
} jnd_display;
void jnd_display_defaults(jnd_display *d);
jnd_status jnd_display_preset(const char *name, jnd_display *d);
const char *const *jnd_display_preset_names(void);
double jnd_ppd_from_geometry(double diagonal_in, int width_px, int height_px, double distance_m);

typedef struct {
  jnd_display display;
  double beta;
  int has_gaze;
  double gaze_x, gaze_y;
  int threads;
  ...;
} jnd_model_params;
void jnd_model_defaults(jnd_model_params *p);

typedef struct jnd_model jnd_model;
jnd_status jnd_model_create(const jnd_model_params *p, jnd_model **out);
void jnd_model_free(jnd_model *m);
int jnd_model_band_peaks(const jnd_model *m, double *cpd, int max);

typedef struct { ...; } jnd_diff_inputs;

typedef enum { JND_POOL_PERCENTILE, JND_POOL_MAX, JND_POOL_MEAN, JND_POOL_MINKOWSKI } jnd_pool_kind;
typedef struct { jnd_pool_kind kind; double percentile; } jnd_pooling;
jnd_status jnd_pooling_parse(const char *s, jnd_pooling *out);

typedef struct {
  double p_detect;
  double p_p50, p_p93, p_p99, p_max, p_mean;
  double jnd_mean, jnd_p93, jnd_max;
  double jnd_minkowski;
} jnd_diff_stats;
double jnd_probability(double jnd, double beta);
jnd_status jnd_diff_files(jnd_model *m, jnd_image *ref, const jnd_image_info *ref_info,
                          jnd_image *test, const jnd_image_info *test_info,
                          const jnd_diff_inputs *in, const jnd_pooling *pool,
                          jnd_image *jnd_out, jnd_diff_stats *stats);
"""


def ffibuilder(include_dir, lib_dir):
    from cffi import FFI

    ffi = FFI()
    ffi.cdef(CDEF)
    ffi.set_source(
        "jnd._jnd_cffi",
        '#include "jnd.h"',
        include_dirs=[os.path.abspath(include_dir)],
        library_dirs=[os.path.abspath(lib_dir)],
        libraries=["jnd"],
        extra_link_args=["-Wl,-rpath," + os.path.abspath(lib_dir)],
        extra_compile_args=os.environ.get("JND_PY_CFLAGS", "").split(),
    )
    return ffi


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--include", required=True, help="the folder holding jnd.h")
    ap.add_argument("--libdir", required=True, help="the folder holding libjnd.so")
    ap.add_argument("--out", required=True, help="the folder to put the package jnd/ in")
    a = ap.parse_args(argv)
    here = os.path.dirname(os.path.abspath(__file__))
    pkg = os.path.join(a.out, "jnd")
    os.makedirs(pkg, exist_ok=True)
    for f in os.listdir(here):
        if f.endswith(".py"):
            shutil.copy2(os.path.join(here, f), os.path.join(pkg, f))
    tmp = os.path.join(a.out, "_cffi_build")
    ffibuilder(a.include, a.libdir).compile(tmpdir=tmp, verbose=False, target=None)
    for f in os.listdir(os.path.join(tmp, "jnd")):
        if f.startswith("_jnd_cffi") and f.endswith(".so"):
            shutil.copy2(os.path.join(tmp, "jnd", f), os.path.join(pkg, f))
            return 0
    print("jnd._build: the extension was not built", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
