/* Internal pieces of the renderer. */
#ifndef JND_RENDER_H
#define JND_RENDER_H

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <GL/glcorearb.h>
#include <stddef.h>
#include <stdint.h>

#include "jnd.h"

/* The GLSL sources embedded at build time (src/render/shaders/NAME.glsl). */
const char *jnd_shader_source(const char *name);

/* ---- EGL context (egl.c) ---- */
typedef struct {
  EGLDisplay display;
  EGLContext context;
  char platform[32];     /* "device" or "surfaceless" */
} jnd_gl_context;

/* Opens a display on the platform asked for ("auto", "device",
 * "surfaceless"; NULL = $JND_EGL_PLATFORM or auto) and makes an OpenGL 4.5
 * core context current without a surface. */
jnd_status jnd_gl_open(const char *platform, jnd_gl_context *ctx);
void jnd_gl_close(jnd_gl_context *ctx);
/* Makes the context current on this thread if it is not. */
void jnd_gl_use(const jnd_gl_context *ctx);

/* ---- environment lighting (environment.c) ---- */
enum { JND_ENV_W = 256, JND_ENV_H = 128, JND_ENV_LEVELS = 6, JND_BRDF_LUT = 32 };

typedef struct {
  /* prefiltered specular, one equirectangular image per mip level; level L
   * is for roughness L / (JND_ENV_LEVELS − 1); RGB float, interleaved */
  float *level[JND_ENV_LEVELS];
  int lw[JND_ENV_LEVELS], lh[JND_ENV_LEVELS];
  float sh[9][3];        /* irradiance / π as spherical harmonics (cosine-convolved) */
  float *brdf_lut;       /* JND_BRDF_LUT² × 2: split-sum scale and bias over (N·V, roughness) */
  float *background;     /* the environment at full resolution for the background, RGB interleaved */
  int bw, bh;
} jnd_environment;

/* The built-in neutral studio: a soft grey dome, a darker floor and three
 * rectangular soft boxes (linear RGB). */
jnd_status jnd_env_studio(jnd_image *out);
/* Prepares the lighting of an equirectangular linear RGB image. */
jnd_status jnd_env_prepare(const jnd_image *equirect, jnd_environment *env);
void jnd_env_free(jnd_environment *env);

/* ---- partial re-rendering (renderer.c), for the judge ---- */
/* Keeps the multisampled depth of the last jnd_render (a handle to free with
 * jnd_render_drop_depth). */
jnd_status jnd_render_keep_depth(jnd_renderer *r, unsigned *handle);
void jnd_render_drop_depth(jnd_renderer *r, unsigned handle);
/* Re-renders the rectangle (x0, y0, w, h) (pixels, row 0 at the top) of view
 * with that view's kept depth, drawing only the meshes whose material has
 * only[material] set, depth test GL_EQUAL: out (allocated, w × h × 4) gets
 * their resolved samples, linear RGB premultiplied by coverage, and the
 * coverage in channel 3; zero where they have no sample. Opaque and
 * alpha-masked materials only (a blended one would need what is behind it). */
jnd_status jnd_render_materials(jnd_renderer *r, const jnd_scene *scene, const jnd_view *view, unsigned depth,
                                const unsigned char *only, int x0, int y0, int w, int h, jnd_image *out);

/* ---- small matrix helpers (views.c); column-major 4 × 4 ---- */
void jnd_mat4_identity(double m[16]);
void jnd_mat4_mul(const double a[16], const double b[16], double out[16]);
void jnd_mat4_look_at(const double eye[3], const double target[3], const double up[3], double out[16]);
void jnd_mat4_perspective(double fov_y_deg, double aspect, double znear, double zfar, double out[16]);
/* The inverse-transpose of the upper 3 × 3 of m. */
void jnd_mat3_normal(const double m[16], double out[9]);
int jnd_mat4_invert(const double m[16], double out[16]);

#endif
