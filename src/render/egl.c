/* A headless OpenGL 4.5 core context: the EGL device platform (a GPU, no
 * window system) when one is there, else Mesa's surfaceless platform
 * (llvmpipe on the CPU). Chosen at run time. */
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core.h"
#include "render/render.h"

static int has_ext(const char *list, const char *ext) {
  if (!list) return 0;
  size_t n = strlen(ext);
  for (const char *p = list; (p = strstr(p, ext)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == 0)) return 1;
  return 0;
}

static jnd_status make_context(EGLDisplay dpy, jnd_gl_context *ctx) {
  EGLint major, minor;
  if (!eglInitialize(dpy, &major, &minor)) return JND_ERR_GL;
  if (!eglBindAPI(EGL_OPENGL_API)) return JND_ERR_GL;
  const char *ext = eglQueryString(dpy, EGL_EXTENSIONS);
  if (!has_ext(ext, "EGL_KHR_surfaceless_context")) return JND_ERR_GL;
  EGLConfig cfg = NULL;
  EGLint ncfg = 0;
  const EGLint cattr[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
  const EGLint cattr_none[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  if (!eglChooseConfig(dpy, cattr, &cfg, 1, &ncfg) || ncfg < 1)
    if (!eglChooseConfig(dpy, cattr_none, &cfg, 1, &ncfg) || ncfg < 1) cfg = NULL;
  const EGLint attr[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                         EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext c = eglCreateContext(dpy, cfg, EGL_NO_CONTEXT, attr);
  if (c == EGL_NO_CONTEXT || !eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c)) {
    if (c != EGL_NO_CONTEXT) eglDestroyContext(dpy, c);
    return JND_ERR_GL;   /* the display stays initialised: see jnd_gl_close */
  }
  ctx->display = dpy;
  ctx->context = c;
  return JND_OK;
}

/* The first hardware device (skipping Mesa's software device), or the
 * software one when allow_software. */
static jnd_status try_device(jnd_gl_context *ctx, int allow_software) {
  PFNEGLQUERYDEVICESEXTPROC query = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
  PFNEGLQUERYDEVICESTRINGEXTPROC qstr =
      (PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
  PFNEGLGETPLATFORMDISPLAYEXTPROC getdpy =
      (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
  if (!query || !qstr || !getdpy) return JND_ERR_GL;
  EGLDeviceEXT dev[16];
  EGLint n = 0;
  if (!query(16, dev, &n)) return JND_ERR_GL;
  for (int i = 0; i < n; i++) {
    const char *ext = qstr(dev[i], EGL_EXTENSIONS);
    if (!allow_software && has_ext(ext, "EGL_MESA_device_software")) continue;
    EGLDisplay dpy = getdpy(EGL_PLATFORM_DEVICE_EXT, dev[i], NULL);
    if (dpy == EGL_NO_DISPLAY) continue;
    if (make_context(dpy, ctx) == JND_OK) {
      snprintf(ctx->platform, sizeof ctx->platform, "device");
      return JND_OK;
    }
  }
  return JND_ERR_GL;
}

static jnd_status try_surfaceless(jnd_gl_context *ctx) {
  PFNEGLGETPLATFORMDISPLAYEXTPROC getdpy =
      (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
  const char *cext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!getdpy || !has_ext(cext, "EGL_MESA_platform_surfaceless")) return JND_ERR_GL;
  EGLDisplay dpy = getdpy(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
  if (dpy == EGL_NO_DISPLAY) return JND_ERR_GL;
  if (make_context(dpy, ctx) != JND_OK) return JND_ERR_GL;
  snprintf(ctx->platform, sizeof ctx->platform, "surfaceless");
  return JND_OK;
}

jnd_status jnd_gl_open(const char *platform, jnd_gl_context *ctx) {
  memset(ctx, 0, sizeof *ctx);
  if (!platform || !*platform) platform = getenv("JND_EGL_PLATFORM");
  if (!platform || !*platform) platform = "auto";
  jnd_status st = JND_ERR_GL;
  if (strcmp(platform, "device") == 0) {
    st = try_device(ctx, 1);
  } else if (strcmp(platform, "surfaceless") == 0) {
    st = try_surfaceless(ctx);
  } else if (strcmp(platform, "auto") == 0) {
    st = try_device(ctx, 0);                 /* a GPU when there is one */
    if (st) st = try_surfaceless(ctx);       /* else Mesa (llvmpipe) */
    if (st) st = try_device(ctx, 1);
  } else {
    return jnd_fail(JND_ERR_ARG, "EGL platform '%s' is not auto, device or surfaceless", platform);
  }
  if (st)
    return jnd_fail(JND_ERR_GL, "no OpenGL 4.5 core context on the EGL %s platform (EGL error 0x%x)",
                    platform, (unsigned)eglGetError());
  return JND_OK;
}

void jnd_gl_use(const jnd_gl_context *ctx) {
  /* several renderers in one thread (a judge and a held-out judge, two tests'
   * renderers) each draw in their own context */
  if (ctx->context && eglGetCurrentContext() != ctx->context)
    eglMakeCurrent(ctx->display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx->context);
}

void jnd_gl_close(jnd_gl_context *ctx) {
  if (!ctx->display) return;
  eglMakeCurrent(ctx->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (ctx->context) eglDestroyContext(ctx->display, ctx->context);
  /* No eglTerminate: an EGL display is one per process and platform, shared
   * by every renderer in it, so terminating it would pull the contexts of
   * other live renderers away. It is released at process exit. */
  eglReleaseThread();
  memset(ctx, 0, sizeof *ctx);
}
