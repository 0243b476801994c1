/* The renderer: GL resources of a scene, the PBR pass (4× MSAA, resolved),
 * the auxiliary pass (depth, motion, mip levels, one sample per pixel) and
 * read-back into jnd_images. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/core.h"
#include "core/fastmath.h"
#include "render/render.h"
#include "scene/scene.h"

/* One level of detail of a mesh as uploaded. */
typedef struct {
  GLuint vao, vbo, ibo;
  int own_vbo;          /* 0: vbo is the mesh's level-0 vertices (base_vbo), shared */
  GLsizei count;
  double centre[3];
  uint64_t version;     /* the jnd_mesh version uploaded */
  uint64_t used;        /* when last drawn (the renderer's tick): the oldest goes first */
} gpu_level;

/* Levels kept uploaded per mesh: a search that switches between levels
 * (pop's pairs, lod's judgements) draws each from memory instead of
 * uploading it again at every switch — on a 100 K-triangle mesh 5 MB a
 * switch, a third of a rendering's time on llvmpipe. */
enum { GPU_LEVELS_KEPT = 16 };

typedef struct {
  gpu_level level[GPU_LEVELS_KEPT];
  int nlevels, now;     /* uploaded; the one drawn */
  GLuint base_vbo;      /* level 0's vertices, which simplified levels index (0: none yet) */
  int material;
} gpu_mesh;

typedef struct {
  GLuint tex;
  uint64_t version;
  int w, h, levels;
} gpu_map;

struct jnd_renderer {
  jnd_gl_context gl;
  char desc[320];
  int w, h, samples;
  int sample_shading;   /* shade every MSAA sample (jnd_renderer_params.pixel_shading 0) */
  float max_aniso;
  /* the PBR program in six variants: [pass][alpha mask], pass 0 shaded
   * colour, 1 auxiliary, 2 unlit colour; only the masked variant may
   * discard, so that the others keep early depth tests */
  GLuint prog[3][2], bg_prog, empty_vao;
  GLuint msaa_fbo, msaa_color, msaa_depth;
  GLuint resolve_fbo, resolve_color;
  GLuint aux_fbo, aux_tex[3], aux_depth;
  GLuint env_tex, bg_tex, brdf_tex;
  float sh[9][3];
  /* the scene uploaded now */
  uint64_t scene_id;
  gpu_mesh *meshes;
  int nmeshes;
  gpu_map *maps;
  int nmaps;
  uint64_t tick;        /* counts level selections (gpu_level.used) */
  float *readbuf;
};

void jnd_renderer_defaults(jnd_renderer_params *p) {
  memset(p, 0, sizeof *p);
  p->width = p->height = 512;
  p->samples = 4;
  p->anisotropy = 8;
}

const char *jnd_renderer_description(const jnd_renderer *r) { return r->desc; }

static jnd_status gl_check(const char *what) {
  GLenum e = glGetError();
  if (e != GL_NO_ERROR) return jnd_fail(JND_ERR_GL, "OpenGL error 0x%x in %s", (unsigned)e, what);
  return JND_OK;
}

/* Compiles and links a program; defines (may be "") go right after the
 * #version line of both stages. */
static jnd_status compile(const char *vs_name, const char *fs_name, const char *defines, GLuint *out) {
  const char *src[2] = {jnd_shader_source(vs_name), jnd_shader_source(fs_name)};
  GLenum type[2] = {GL_VERTEX_SHADER, GL_FRAGMENT_SHADER};
  GLuint sh[2] = {0, 0}, prog = glCreateProgram();
  for (int i = 0; i < 2; i++) {
    if (!src[i]) return jnd_fail(JND_ERR_INTERNAL, "shader %s is not embedded", i ? fs_name : vs_name);
    const char *nl = strchr(src[i], '\n');
    if (!nl) return jnd_fail(JND_ERR_INTERNAL, "shader %s has no #version line", i ? fs_name : vs_name);
    const char *parts[3] = {src[i], defines, nl + 1};
    GLint lens[3] = {(GLint)(nl + 1 - src[i]), (GLint)strlen(defines), -1};
    sh[i] = glCreateShader(type[i]);
    glShaderSource(sh[i], 3, parts, lens);
    glCompileShader(sh[i]);
    GLint ok = 0;
    glGetShaderiv(sh[i], GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[1024] = "";
      glGetShaderInfoLog(sh[i], sizeof log, NULL, log);
      for (char *p = log; *p; p++)
        if (*p == '\n') *p = ' ';
      return jnd_fail(JND_ERR_INTERNAL, "shader %s: %s", i ? fs_name : vs_name, log);
    }
    glAttachShader(prog, sh[i]);
  }
  glLinkProgram(prog);
  for (int i = 0; i < 2; i++) glDeleteShader(sh[i]);
  GLint ok = 0;
  glGetProgramiv(prog, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[1024] = "";
    glGetProgramInfoLog(prog, sizeof log, NULL, log);
    for (char *p = log; *p; p++)
      if (*p == '\n') *p = ' ';
    glDeleteProgram(prog);
    return jnd_fail(JND_ERR_INTERNAL, "shader program %s: %s", fs_name, log);
  }
  *out = prog;
  return JND_OK;
}

static void delete_targets(jnd_renderer *r) {
  GLuint fb[3] = {r->msaa_fbo, r->resolve_fbo, r->aux_fbo};
  glDeleteFramebuffers(3, fb);
  GLuint rb[5] = {r->msaa_color, r->msaa_depth, r->aux_depth, r->resolve_color, 0};
  glDeleteRenderbuffers(4, rb);
  glDeleteTextures(3, r->aux_tex);
  r->msaa_fbo = r->resolve_fbo = r->aux_fbo = 0;
  r->msaa_color = r->msaa_depth = r->aux_depth = r->resolve_color = 0;
  memset(r->aux_tex, 0, sizeof r->aux_tex);
  free(r->readbuf);
  r->readbuf = NULL;
}

static jnd_status make_targets(jnd_renderer *r) {
  int w = r->w, h = r->h;
  glCreateRenderbuffers(1, &r->msaa_color);
  glCreateRenderbuffers(1, &r->msaa_depth);
  glNamedRenderbufferStorageMultisample(r->msaa_color, r->samples, GL_RGBA32F, w, h);
  glNamedRenderbufferStorageMultisample(r->msaa_depth, r->samples, GL_DEPTH_COMPONENT32F, w, h);
  glCreateFramebuffers(1, &r->msaa_fbo);
  glNamedFramebufferRenderbuffer(r->msaa_fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, r->msaa_color);
  glNamedFramebufferRenderbuffer(r->msaa_fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->msaa_depth);

  glCreateRenderbuffers(1, &r->resolve_color);
  glNamedRenderbufferStorage(r->resolve_color, GL_RGBA32F, w, h);
  glCreateFramebuffers(1, &r->resolve_fbo);
  glNamedFramebufferRenderbuffer(r->resolve_fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, r->resolve_color);

  glCreateTextures(GL_TEXTURE_2D, 3, r->aux_tex);
  glCreateRenderbuffers(1, &r->aux_depth);
  glNamedRenderbufferStorage(r->aux_depth, GL_DEPTH_COMPONENT32F, w, h);
  glCreateFramebuffers(1, &r->aux_fbo);
  for (int i = 0; i < 3; i++) {
    glTextureStorage2D(r->aux_tex[i], 1, GL_RGBA32F, w, h);
    glNamedFramebufferTexture(r->aux_fbo, GL_COLOR_ATTACHMENT1 + i, r->aux_tex[i], 0);
  }
  glNamedFramebufferRenderbuffer(r->aux_fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->aux_depth);
  GLenum aux_bufs[4] = {GL_NONE, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2, GL_COLOR_ATTACHMENT3};
  glNamedFramebufferDrawBuffers(r->aux_fbo, 4, aux_bufs);
  GLenum fbs[3] = {r->msaa_fbo, r->resolve_fbo, r->aux_fbo};
  for (int i = 0; i < 3; i++)
    if (glCheckNamedFramebufferStatus(fbs[i], GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      return jnd_fail(JND_ERR_GL, "render target %d × %d (%d samples) is not supported", w, h, r->samples);
  r->readbuf = jnd_alloc((size_t)w * h * 4, sizeof(float));
  if (!r->readbuf) return JND_ERR_NOMEM;
  return gl_check("render targets");
}

static GLuint env_texture(GLenum internal, GLenum format, int w, int h, int levels, float *const *data,
                          const int *lw, const int *lh, GLenum min_filter, GLenum wrap_s) {
  GLuint t;
  glCreateTextures(GL_TEXTURE_2D, 1, &t);
  glTextureStorage2D(t, levels, internal, w, h);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (int l = 0; l < levels; l++) glTextureSubImage2D(t, l, 0, 0, lw[l], lh[l], format, GL_FLOAT, data[l]);
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, min_filter);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, wrap_s);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_MAX_LEVEL, levels - 1);
  return t;
}

/* The last prepared environment, kept for the next renderer: prefiltering
 * takes 0.35 s of the 0.41 s a renderer takes to open, and a run opens
 * several on the same environment (calibration's series, the tests). Keyed
 * by the file's path and identity (device, inode, size, modification time:
 * a file rewritten in between is prepared again), or the studio. One entry,
 * kept until the process ends (a few hundred KB); the lock makes renderers
 * opened on several threads safe. */
static pthread_mutex_t env_lock = PTHREAD_MUTEX_INITIALIZER;
static struct {
  int held, valid, studio;   /* env holds an environment; it is path's (or the studio's) */
  char *path;
  struct stat id;
  jnd_environment env;
} env_cache;

static int same_file(const struct stat *a, const struct stat *b) {
  return a->st_dev == b->st_dev && a->st_ino == b->st_ino && a->st_size == b->st_size &&
         a->st_mtim.tv_sec == b->st_mtim.tv_sec && a->st_mtim.tv_nsec == b->st_mtim.tv_nsec;
}

/* Prepares the environment of path (NULL: the studio) into the cache, unless
 * it is there already. Called with env_lock held. */
static jnd_status cached_environment(const char *path) {
  struct stat id;
  memset(&id, 0, sizeof id);
  int known = path && stat(path, &id) == 0;
  if (env_cache.valid && (path ? known && env_cache.path && !strcmp(env_cache.path, path) && same_file(&env_cache.id, &id)
                               : env_cache.studio))
    return JND_OK;
  jnd_image eq = {0};
  jnd_status st;
  if (path) {
    jnd_image_info info;
    if ((st = jnd_image_read(path, &eq, &info))) return st;
    if (info.encoding != JND_ENCODING_LINEAR) {
      jnd_image_free(&eq);
      return jnd_fail(JND_ERR_FORMAT, "%s: an environment must be linear (.hdr or .exr)", path);
    }
    if (eq.w < 8 || eq.h < 4) {
      jnd_image_free(&eq);
      return jnd_fail(JND_ERR_FORMAT, "%s: environment too small (%d × %d)", path, eq.w, eq.h);
    }
  } else if ((st = jnd_env_studio(&eq))) {
    return st;
  }
  jnd_environment env;
  char *copy = path ? strdup(path) : NULL;
  st = path && !copy ? JND_ERR_NOMEM : jnd_env_prepare(&eq, &env);
  jnd_image_free(&eq);
  if (st) {
    free(copy);
    return st;
  }
  if (env_cache.held) jnd_env_free(&env_cache.env);
  free(env_cache.path);
  env_cache.held = 1;
  env_cache.env = env;
  env_cache.valid = known || !path;   /* a file stat could not identify is prepared each time */
  env_cache.studio = !path;
  env_cache.path = copy;
  env_cache.id = id;
  return JND_OK;
}

static jnd_status load_environment(jnd_renderer *r, const char *path) {
  pthread_mutex_lock(&env_lock);
  jnd_status st = cached_environment(path);
  if (st) {
    pthread_mutex_unlock(&env_lock);
    return st;
  }
  jnd_environment *env = &env_cache.env;
  r->env_tex = env_texture(GL_RGB32F, GL_RGB, JND_ENV_W, JND_ENV_H, JND_ENV_LEVELS, env->level, env->lw, env->lh,
                           GL_LINEAR_MIPMAP_LINEAR, GL_REPEAT);
  r->bg_tex = env_texture(GL_RGB32F, GL_RGB, env->bw, env->bh, 1, &env->background, &env->bw, &env->bh, GL_LINEAR,
                          GL_REPEAT);
  int n = JND_BRDF_LUT;
  r->brdf_tex = env_texture(GL_RG32F, GL_RG, n, n, 1, &env->brdf_lut, &n, &n, GL_LINEAR, GL_CLAMP_TO_EDGE);
  memcpy(r->sh, env->sh, sizeof r->sh);
  pthread_mutex_unlock(&env_lock);
  return gl_check("environment textures");
}

jnd_status jnd_renderer_create(const jnd_renderer_params *p, jnd_renderer **out) {
  jnd_renderer_params d;
  if (!p) {
    jnd_renderer_defaults(&d);
    p = &d;
  }
  *out = NULL;
  if (p->width < 1 || p->height < 1 || p->width > 16384 || p->height > 16384)
    return jnd_fail(JND_ERR_ARG, "renderer: size %d × %d outside 1..16384", p->width, p->height);
  jnd_renderer *r = jnd_calloc(1, sizeof *r);
  if (!r) return JND_ERR_NOMEM;
  jnd_status st = jnd_gl_open(p->platform, &r->gl);
  if (st) {
    free(r);
    return st;
  }
  snprintf(r->desc, sizeof r->desc, "%s (%s)", (const char *)glGetString(GL_RENDERER), r->gl.platform);
  r->w = p->width;
  r->h = p->height;
  GLint max_samples = 1;
  glGetInternalformativ(GL_RENDERBUFFER, GL_RGBA32F, GL_SAMPLES, 1, &max_samples);
  r->samples = jnd_clampi(p->samples > 0 ? p->samples : 1, 1, max_samples > 0 ? max_samples : 1);
  r->sample_shading = !p->pixel_shading && r->samples > 1;
  /* anisotropic filtering is the shader's (pbr_frag.glsl, sample_map): the
   * same on every driver, whatever it offers */
  r->max_aniso = (float)jnd_clampi(p->anisotropy, 1, 16);
  static const char *const variants[3][2] = {{"", "#define JND_ALPHA_MASK 1\n"},
                                             {"#define JND_AUX 1\n", "#define JND_AUX 1\n#define JND_ALPHA_MASK 1\n"},
                                             {"#define JND_UNLIT 1\n", "#define JND_UNLIT 1\n#define JND_ALPHA_MASK 1\n"}};
  for (int a = 0; a < 3 && !st; a++)
    for (int m = 0; m < 2 && !st; m++) st = compile("pbr_vert", "pbr_frag", variants[a][m], &r->prog[a][m]);
  if (st || (st = compile("bg_vert", "bg_frag", "", &r->bg_prog)) ||
      (st = make_targets(r)) || (st = load_environment(r, p->env_path))) {
    jnd_renderer_free(r);
    return st;
  }
  glCreateVertexArrays(1, &r->empty_vao);
  *out = r;
  return gl_check("renderer setup");
}

/* deletes level i of g's uploaded levels (the last takes its place) */
static void drop_level(gpu_mesh *g, int i) {
  gpu_level *l = &g->level[i];
  glDeleteVertexArrays(1, &l->vao);
  if (l->own_vbo) glDeleteBuffers(1, &l->vbo);
  glDeleteBuffers(1, &l->ibo);
  *l = g->level[--g->nlevels];
}

static void drop_scene(jnd_renderer *r) {
  for (int i = 0; i < r->nmeshes; i++) {
    gpu_mesh *g = &r->meshes[i];
    while (g->nlevels > 0) drop_level(g, g->nlevels - 1);
    glDeleteBuffers(1, &g->base_vbo);
  }
  for (int i = 0; i < r->nmaps; i++) glDeleteTextures(1, &r->maps[i].tex);
  free(r->meshes);
  free(r->maps);
  r->meshes = NULL;
  r->maps = NULL;
  r->nmeshes = r->nmaps = 0;
  r->scene_id = 0;
}

void jnd_renderer_free(jnd_renderer *r) {
  if (!r) return;
  if (r->gl.context) {
    jnd_gl_use(&r->gl);
    drop_scene(r);
    delete_targets(r);
    for (int a = 0; a < 3; a++)
      for (int m = 0; m < 2; m++) glDeleteProgram(r->prog[a][m]);
    glDeleteProgram(r->bg_prog);
    GLuint t[3] = {r->env_tex, r->bg_tex, r->brdf_tex};
    glDeleteTextures(3, t);
    glDeleteVertexArrays(1, &r->empty_vao);
  }
  jnd_gl_close(&r->gl);
  free(r->readbuf);
  free(r);
}

void jnd_renderer_size(const jnd_renderer *r, int *width, int *height) {
  *width = r->w;
  *height = r->h;
}

jnd_status jnd_renderer_resize(jnd_renderer *r, int width, int height) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    return jnd_fail(JND_ERR_ARG, "renderer: size %d × %d outside 1..16384", width, height);
  if (width == r->w && height == r->h) return JND_OK;
  jnd_gl_use(&r->gl);
  delete_targets(r);
  r->w = width;
  r->h = height;
  return make_targets(r);
}

/* ---- scene upload ---- */

static jnd_status upload_map(jnd_renderer *r, const jnd_map *m, jnd_map_slot slot, gpu_map *g) {
  const jnd_image *img = jnd_map_image(m);
  int w = img->w, h = img->h, c = img->c;
  if (g->tex) glDeleteTextures(1, &g->tex);
  unsigned char *px = jnd_alloc((size_t)w * h, 4);
  if (!px) return JND_ERR_NOMEM;
  size_t P = (size_t)w * h;
  for (size_t i = 0; i < P; i++)
    for (int k = 0; k < 4; k++) {
      float v;
      if (c >= 3) v = k < c ? img->data[k * P + i] : 1.0f;
      else v = k < 3 ? img->data[i] : (c == 2 ? img->data[P + i] : 1.0f);
      px[i * 4 + k] = (unsigned char)lrintf(255.0f * (float)jnd_clampd(v, 0, 1));
    }
  int levels = 1;
  while ((w >> levels) > 0 || (h >> levels) > 0) levels++;
  int colour = jnd_map_slot_kind(slot) == JND_MAP_KIND_COLOR;
  glCreateTextures(GL_TEXTURE_2D, 1, &g->tex);
  glTextureStorage2D(g->tex, levels, colour ? GL_SRGB8_ALPHA8 : GL_RGBA8, w, h);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(g->tex, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px);
  free(px);
  glGenerateTextureMipmap(g->tex);
  GLenum wrap[3] = {GL_REPEAT, GL_CLAMP_TO_EDGE, GL_MIRRORED_REPEAT};
  glTextureParameteri(g->tex, GL_TEXTURE_WRAP_S, (GLint)wrap[m->wrap_s]);
  glTextureParameteri(g->tex, GL_TEXTURE_WRAP_T, (GLint)wrap[m->wrap_t]);
  glTextureParameteri(g->tex, GL_TEXTURE_MIN_FILTER,
                      m->min_nearest ? GL_NEAREST_MIPMAP_LINEAR : GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(g->tex, GL_TEXTURE_MAG_FILTER, m->mag_nearest ? GL_NEAREST : GL_LINEAR);
  g->version = m->version;
  g->w = w;
  g->h = h;
  g->levels = levels;
  return gl_check("texture upload");
}

/* GL buffers of (count) floats or indices, at least one element: a level may
 * have no triangles, and GL buffers of size 0 are not allowed */
static GLuint buffer_of(const void *data, size_t count, size_t size) {
  GLuint b;
  glCreateBuffers(1, &b);
  glNamedBufferStorage(b, (GLsizeiptr)((count ? count : 1) * size), count ? data : NULL, 0);
  return b;
}

/* Makes level m of scene mesh i the one g draws: from the levels uploaded
 * (by the mesh's version), or uploaded now, in place of the level drawn
 * longest ago when GPU_LEVELS_KEPT are. A level that indexes level 0's
 * vertices (a simplified level, jnd_lod_mesh.vertices NULL) shares one
 * buffer of them: level 0's arrays live as long as the scene (lod.c). */
static void use_mesh(jnd_renderer *r, const jnd_scene *s, int i, gpu_mesh *g) {
  const jnd_mesh *m = &s->meshes[i];
  g->material = m->material;
  for (int k = 0; k < g->nlevels; k++)
    if (g->level[k].version == m->version) {
      g->now = k;
      g->level[k].used = ++r->tick;
      return;
    }
  if (g->nlevels == GPU_LEVELS_KEPT) {
    int old = 0;
    for (int k = 1; k < g->nlevels; k++)
      if (g->level[k].used < g->level[old].used) old = k;
    drop_level(g, old);
  }
  gpu_level *l = &g->level[g->nlevels];
  memset(l, 0, sizeof *l);
  const jnd_lod_mesh *base = s->nlod > 0 ? &s->lod[0].mesh[i] : NULL;
  if (base && m->vertices == base->vertices && m->nverts == base->nverts) {
    if (!g->base_vbo) g->base_vbo = buffer_of(m->vertices, m->nverts, JND_VTX_FLOATS * sizeof(float));
    l->vbo = g->base_vbo;
  } else {
    l->vbo = buffer_of(m->vertices, m->nverts, JND_VTX_FLOATS * sizeof(float));
    l->own_vbo = 1;
  }
  l->ibo = buffer_of(m->indices, 3 * m->ntris, sizeof(uint32_t));
  glCreateVertexArrays(1, &l->vao);
  glVertexArrayVertexBuffer(l->vao, 0, l->vbo, 0, JND_VTX_FLOATS * sizeof(float));
  glVertexArrayElementBuffer(l->vao, l->ibo);
  static const int comps[6] = {3, 3, 4, 2, 2, 4}, offs[6] = {0, 3, 6, 10, 12, 14};
  for (int a = 0; a < 6; a++) {
    glEnableVertexArrayAttrib(l->vao, a);
    glVertexArrayAttribFormat(l->vao, a, comps[a], GL_FLOAT, GL_FALSE, offs[a] * sizeof(float));
    glVertexArrayAttribBinding(l->vao, a, 0);
  }
  l->count = (GLsizei)(m->ntris * 3);
  l->version = m->version;
  l->used = ++r->tick;
  double acc[3] = {0, 0, 0};
  for (size_t v = 0; v < m->nverts; v++)
    for (int k = 0; k < 3; k++) acc[k] += m->vertices[v * JND_VTX_FLOATS + k];
  for (int k = 0; k < 3; k++) l->centre[k] = m->nverts ? acc[k] / m->nverts : 0;
  g->now = g->nlevels++;
}

static jnd_status sync_scene(jnd_renderer *r, const jnd_scene *s) {
  if (r->scene_id != s->id) {
    drop_scene(r);
    r->meshes = jnd_calloc(s->nmeshes ? (size_t)s->nmeshes : 1, sizeof *r->meshes);
    r->maps = jnd_calloc(s->nmaps ? (size_t)s->nmaps : 1, sizeof *r->maps);
    if (!r->meshes || !r->maps) return JND_ERR_NOMEM;
    r->nmeshes = s->nmeshes;
    r->nmaps = s->nmaps;
    r->scene_id = s->id;
  }
  for (int i = 0; i < r->nmeshes; i++) {   /* a level of detail selected since, or none yet */
    gpu_mesh *g = &r->meshes[i];
    if (g->nlevels == 0 || g->level[g->now].version != s->meshes[i].version) use_mesh(r, s, i, g);
  }
  for (int i = 0; i < s->nmaps; i++) {
    if (r->maps[i].tex && r->maps[i].version == s->maps[i].version) continue;
    int slot = 0;
    for (int m = 0; m < s->nmaterials; m++)
      for (int k = 0; k < JND_MAP_SLOTS; k++)
        if (s->materials[m].map[k] == i) slot = k;
    jnd_status st = upload_map(r, &s->maps[i], (jnd_map_slot)slot, &r->maps[i]);
    if (st) return st;
  }
  return gl_check("scene upload");
}

/* ---- drawing ---- */

static GLint U(GLuint prog, const char *name) { return glGetUniformLocation(prog, name); }

static void set_mat4(GLuint prog, const char *name, const double m[16]) {
  float f[16];
  for (int i = 0; i < 16; i++) f[i] = (float)m[i];
  glProgramUniformMatrix4fv(prog, U(prog, name), 1, GL_FALSE, f);
}

static void env_rotation(double deg, float out[9]) {
  double a = deg * M_PI / 180, c = cos(a), s = sin(a);
  /* rotation about +Y, column-major */
  float m[9] = {(float)c, 0, (float)-s, 0, 1, 0, (float)s, 0, (float)c};
  memcpy(out, m, sizeof m);
}

static void camera_matrices(const jnd_scene *s, const jnd_camera *c, double aspect, double view[16],
                            double proj[16]) {
  jnd_mat4_look_at(c->eye, c->target, c->up, view);
  double zn = c->znear, zf = c->zfar;
  if (!(zn > 0) || !(zf > zn)) {
    double d = 0;
    for (int k = 0; k < 3; k++) d += (c->eye[k] - s->centre[k]) * (c->eye[k] - s->centre[k]);
    d = sqrt(d);
    zn = fmax(d - 1.5 * s->radius, fmax(d, s->radius) * 1e-3);
    zf = d + 1.5 * s->radius;
  }
  jnd_mat4_perspective(c->fov_y_deg > 0 ? c->fov_y_deg : 45, aspect, zn, zf, proj);
}

static void set_material(jnd_renderer *r, const jnd_scene *s, const jnd_material *m, GLuint p) {
  glProgramUniform4fv(p, U(p, "u_base_color"), 1, m->base_color);
  glProgramUniform1f(p, U(p, "u_metallic"), m->metallic);
  glProgramUniform1f(p, U(p, "u_roughness"), m->roughness);
  glProgramUniform1f(p, U(p, "u_normal_scale"), m->normal_scale);
  glProgramUniform1f(p, U(p, "u_occlusion_strength"), m->occlusion_strength);
  glProgramUniform3fv(p, U(p, "u_emissive"), 1, m->emissive);
  glProgramUniform1i(p, U(p, "u_alpha_mode"), (int)m->alpha_mode);
  glProgramUniform1f(p, U(p, "u_alpha_cutoff"), m->alpha_cutoff);
  GLint has[5], uvset[5];
  float size[10], levels[5], uvxf[30];
  for (int k = 0; k < JND_MAP_SLOTS; k++) {
    int i = m->map[k];
    has[k] = i >= 0 && r->maps[i].tex;
    uvset[k] = has[k] ? s->maps[i].uv_set : 0;
    size[2 * k] = has[k] ? (float)r->maps[i].w : 1;
    size[2 * k + 1] = has[k] ? (float)r->maps[i].h : 1;
    levels[k] = has[k] ? (float)r->maps[i].levels : 1;
    static const float identity[6] = {1, 0, 0, 0, 1, 0};
    memcpy(uvxf + 6 * k, has[k] ? s->maps[i].uvxf : identity, sizeof identity);
    glBindTextureUnit((GLuint)k, has[k] ? r->maps[i].tex : 0);
  }
  glProgramUniform1iv(p, U(p, "u_has"), 5, has);
  glProgramUniform1iv(p, U(p, "u_uvset"), 5, uvset);
  glProgramUniform2fv(p, U(p, "u_size"), 5, size);
  glProgramUniform1fv(p, U(p, "u_levels"), 5, levels);
  glProgramUniform3fv(p, U(p, "u_uvxf"), 10, uvxf);
  if (m->double_sided) glDisable(GL_CULL_FACE);
  else glEnable(GL_CULL_FACE);
}

/* Sort keys: blended meshes last and back to front; the others front to
 * back so that early depth tests spare hidden fragments; ties by index. */
static int by_key(const void *a, const void *b) {
  const double *x = a, *y = b;
  for (int k = 0; k < 3; k++)
    if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
  return 0;
}

/* Draws every mesh (or, with only != NULL, those whose material has
 * only[material] set): opaque and masked first, blended ones after. pass
 * picks the programs: 0 shaded colour, 1 auxiliary, 2 unlit colour. */
static void draw_meshes(jnd_renderer *r, const jnd_scene *s, const double eye[3], int pass,
                        const unsigned char *only) {
  double (*order)[3] = jnd_alloc(r->nmeshes ? (size_t)r->nmeshes : 1, sizeof *order);
  if (!order) return;
  for (int i = 0; i < r->nmeshes; i++) {
    int blend = s->materials[r->meshes[i].material].alpha_mode == JND_ALPHA_BLEND;
    const double *c = r->meshes[i].level[r->meshes[i].now].centre;
    double d = 0;
    for (int k = 0; k < 3; k++) d += (c[k] - eye[k]) * (c[k] - eye[k]);
    order[i][0] = blend;
    order[i][1] = blend ? -d : d;
    order[i][2] = i;
  }
  qsort(order, (size_t)r->nmeshes, sizeof order[0], by_key);
  int blending = 0;
  for (int j = 0; j < r->nmeshes; j++) {
    const gpu_mesh *g = &r->meshes[(int)order[j][2]];
    const jnd_material *m = &s->materials[g->material];
    if (only && !only[g->material]) continue;
    if (order[j][0] > 0 && !blending && pass != 1) {
      glEnablei(GL_BLEND, 0);
      glBlendFunci(0, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);   /* premultiplied */
      glDepthMask(GL_FALSE);
      blending = 1;
    }
    GLuint p = r->prog[pass][m->alpha_mode == JND_ALPHA_MASK];
    glUseProgram(p);
    set_material(r, s, m, p);
    glProgramUniform1f(p, U(p, "u_material"), (float)g->material);
    const gpu_level *l = &g->level[g->now];
    glBindVertexArray(l->vao);
    glDrawElements(GL_TRIANGLES, l->count, GL_UNSIGNED_INT, NULL);
  }
  glDisablei(GL_BLEND, 0);
  glDepthMask(GL_TRUE);
  free(order);
}

/* Reads attachment buf of fbo into planar channels of dst (row 0 at the top). */
static void read_back(jnd_renderer *r, GLuint fbo, GLenum buf, const int *src_ch, int n, jnd_image *dst) {
  glNamedFramebufferReadBuffer(fbo, buf);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, r->w, r->h, GL_RGBA, GL_FLOAT, r->readbuf);
  size_t P = (size_t)r->w * r->h;
  for (int c = 0; c < n; c++)
    for (int y = 0; y < r->h; y++) {
      const float *row = r->readbuf + (size_t)(r->h - 1 - y) * r->w * 4;
      float *d = dst->data + c * P + (size_t)y * r->w;
      for (int x = 0; x < r->w; x++) d[x] = row[x * 4 + src_ch[c]];
    }
}

/* Everything of a view the programs read (matrices, lights, environment),
 * and the fixed-function state of the PBR passes. vp receives the
 * view-projection matrix. */
static jnd_status setup_view(jnd_renderer *r, const jnd_scene *scene, const jnd_view *view, double vp[16]) {
  if (view->nlights < 0 || view->nlights > JND_MAX_LIGHTS)
    return jnd_fail(JND_ERR_ARG, "render: %d lights (at most %d)", view->nlights, JND_MAX_LIGHTS);
  jnd_gl_use(&r->gl);
  jnd_status st = sync_scene(r, scene);
  if (st) return st;
  double aspect = (double)r->w / r->h;
  double vmat[16], proj[16], pv[16], pp[16], pvp[16], prev_mvp[16], nrm[9];
  camera_matrices(scene, &view->camera, aspect, vmat, proj);
  jnd_mat4_mul(proj, vmat, vp);
  const jnd_camera *pc = view->has_prev ? &view->prev_camera : &view->camera;
  const double *pm = view->has_prev ? view->prev_model : view->model;
  camera_matrices(scene, pc, aspect, pv, pp);
  jnd_mat4_mul(pp, pv, pvp);
  jnd_mat4_mul(pvp, pm, prev_mvp);
  /* shading with the previous pose's setup: its model places the point, its eye sees it */
  const int shade_prev = view->shade_prev && view->has_prev;
  const double *sm = shade_prev ? view->prev_model : view->model;
  const double *eye = shade_prev ? view->prev_camera.eye : view->camera.eye;
  jnd_mat3_normal(sm, nrm);

  float nf[9], rot[9];
  for (int i = 0; i < 9; i++) nf[i] = (float)nrm[i];
  env_rotation(view->env_rotation_deg, rot);
  /* lights */
  GLint lt[8] = {0};
  float lpos[24] = {0}, ldir[24] = {0}, lcol[24] = {0}, lrange[8] = {0}, lcone[16] = {0};
  for (int i = 0; i < view->nlights; i++) {
    const jnd_light *L = &view->lights[i];
    lt[i] = (int)L->type;
    for (int k = 0; k < 3; k++) {
      lpos[3 * i + k] = (float)L->position[k];
      ldir[3 * i + k] = (float)L->direction[k];
      lcol[3 * i + k] = (float)(L->color[k] * L->intensity);
    }
    lrange[i] = (float)L->range;
    double inner = L->inner_deg, outer = L->outer_deg > 0 ? L->outer_deg : 45;
    if (inner >= outer) inner = outer * 0.999;
    lcone[2 * i] = (float)cos(inner * M_PI / 180);
    lcone[2 * i + 1] = (float)cos(outer * M_PI / 180);
  }
  for (int pi = 0; pi < 6; pi++) {
    GLuint p = r->prog[pi / 2][pi % 2];
    set_mat4(p, "u_model", view->model);
    set_mat4(p, "u_shade_model", sm);
    set_mat4(p, "u_view", vmat);
    set_mat4(p, "u_viewproj", vp);
    set_mat4(p, "u_prev_mvp", prev_mvp);
    glProgramUniformMatrix3fv(p, U(p, "u_normal_mat"), 1, GL_FALSE, nf);
    glProgramUniform3f(p, U(p, "u_eye"), (float)eye[0], (float)eye[1], (float)eye[2]);
    glProgramUniform2f(p, U(p, "u_viewport"), (float)r->w, (float)r->h);
    glProgramUniform1f(p, U(p, "u_exposure"), (float)view->exposure);
    glProgramUniform1f(p, U(p, "u_max_aniso"), r->max_aniso);
    glProgramUniform1i(p, U(p, "u_nlights"), view->nlights);
    glProgramUniform1iv(p, U(p, "u_ltype"), 8, lt);
    glProgramUniform3fv(p, U(p, "u_lpos"), 8, lpos);
    glProgramUniform3fv(p, U(p, "u_ldir"), 8, ldir);
    glProgramUniform3fv(p, U(p, "u_lcolor"), 8, lcol);
    glProgramUniform1fv(p, U(p, "u_lrange"), 8, lrange);
    glProgramUniform2fv(p, U(p, "u_lcone"), 8, lcone);
    /* environment */
    glProgramUniformMatrix3fv(p, U(p, "u_env_rot"), 1, GL_FALSE, rot);
    glProgramUniform1f(p, U(p, "u_env_intensity"), (float)view->env_intensity);
    glProgramUniform1f(p, U(p, "u_env_levels"), (float)JND_ENV_LEVELS);
    glProgramUniform3fv(p, U(p, "u_sh"), 9, &r->sh[0][0]);
    static const char *const maps[5] = {"u_map0", "u_map1", "u_map2", "u_map3", "u_map4"};
    for (int k = 0; k < 5; k++) glProgramUniform1i(p, U(p, maps[k]), k);
    glProgramUniform1i(p, U(p, "u_env"), 5);
    glProgramUniform1i(p, U(p, "u_brdf"), 6);
  }
  glBindTextureUnit(5, r->env_tex);
  glBindTextureUnit(6, r->brdf_tex);

  glViewport(0, 0, r->w, r->h);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glCullFace(GL_BACK);
  glFrontFace(GL_CCW);
  return JND_OK;
}

/* Shading at every MSAA sample: a pixel is then the mean of the shaded
 * image over its area (coverage and shading alike), as a display pixel
 * shows it, rather than the shading at its centre with only the edges
 * antialiased. Detail finer than a pixel (normals of a dense mesh, specular
 * highlights) then averages out instead of aliasing into coarser patterns,
 * so the same object drawn with more pixels is a better-sampled version of
 * the same image (docs/lod.md "The same image at every pixel count"). */
static void multisample_shading(const jnd_renderer *r) {
  if (r->sample_shading) {
    glEnable(GL_SAMPLE_SHADING);
    glMinSampleShading(1.0f);
  } else {
    glDisable(GL_SAMPLE_SHADING);
  }
}

/* pass 1 of jnd_render: colour and coverage with MSAA, resolved */
static jnd_status colour_pass(jnd_renderer *r, const jnd_scene *scene, const jnd_view *view, const double vp[16]) {
  float rot[9];
  env_rotation(view->env_rotation_deg, rot);
  glBindFramebuffer(GL_FRAMEBUFFER, r->msaa_fbo);
  glEnable(GL_MULTISAMPLE);
  multisample_shading(r);
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(r->msaa_fbo, GL_COLOR, 0, zero);
  glClearNamedFramebufferfi(r->msaa_fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
  if (view->background_env) {
    GLuint b = r->bg_prog;
    double inv[16];
    jnd_mat4_invert(vp, inv);
    glUseProgram(b);
    set_mat4(b, "u_inv_viewproj", inv);
    glProgramUniform3f(b, U(b, "u_eye"), (float)view->camera.eye[0], (float)view->camera.eye[1],
                       (float)view->camera.eye[2]);
    glProgramUniformMatrix3fv(b, U(b, "u_env_rot"), 1, GL_FALSE, rot);
    glProgramUniform1f(b, U(b, "u_env_intensity"), (float)view->env_intensity);
    glProgramUniform1f(b, U(b, "u_exposure"), (float)view->exposure);
    glProgramUniform1i(b, U(b, "u_bg"), 7);
    glBindTextureUnit(7, r->bg_tex);
    glDepthMask(GL_FALSE);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(r->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
  }
  draw_meshes(r, scene, view->camera.eye, view->unlit ? 2 : 0, NULL);
  glBlitNamedFramebuffer(r->msaa_fbo, r->resolve_fbo, 0, 0, r->w, r->h, 0, 0, r->w, r->h,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
  return gl_check("colour pass");
}

jnd_status jnd_render(jnd_renderer *r, const jnd_scene *scene, const jnd_view *view, jnd_frame *frame) {
  memset(frame, 0, sizeof *frame);
  double vp[16];
  jnd_status st = setup_view(r, scene, view, vp);
  if (st) return st;
  unsigned outs = view->outputs ? view->outputs : JND_OUT_COLOR;

  /* pass 1: colour and coverage with MSAA, unless only pass 2's outputs are
   * asked (a previous frame's depth: pop's disocclusion) */
  if ((outs & (JND_OUT_COLOR | JND_OUT_MASK)) && (st = colour_pass(r, scene, view, vp))) return st;
  const float zero[4] = {0, 0, 0, 0};

  /* pass 2: one sample per pixel for depth, motion and mip levels */
  int want_aux = (outs & (JND_OUT_DEPTH | JND_OUT_MOTION | JND_OUT_MIP)) != 0;
  if (want_aux) {
    glBindFramebuffer(GL_FRAMEBUFFER, r->aux_fbo);
    const float none[4] = {-1, -1, -1, -1};
    glClearNamedFramebufferfv(r->aux_fbo, GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(r->aux_fbo, GL_COLOR, 2, none);
    glClearNamedFramebufferfv(r->aux_fbo, GL_COLOR, 3, none);
    glClearNamedFramebufferfi(r->aux_fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    draw_meshes(r, scene, view->camera.eye, 1, NULL);
    if ((st = gl_check("auxiliary pass"))) return st;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);

  /* read back */
  jnd_frame f;
  memset(&f, 0, sizeof f);
  int w = r->w, h = r->h;
  if (outs & JND_OUT_COLOR) {
    if ((st = jnd_image_alloc(&f.color, w, h, 3))) goto fail;
    static const int rgb[3] = {0, 1, 2};
    read_back(r, r->resolve_fbo, GL_COLOR_ATTACHMENT0, rgb, 3, &f.color);
  }
  if (outs & JND_OUT_MASK) {
    if ((st = jnd_image_alloc(&f.mask, w, h, 1))) goto fail;
    static const int a[1] = {3};
    read_back(r, r->resolve_fbo, GL_COLOR_ATTACHMENT0, a, 1, &f.mask);
    for (size_t i = 0; i < (size_t)w * h; i++) f.mask.data[i] = (float)jnd_clampd(f.mask.data[i], 0, 1);
  }
  if (outs & JND_OUT_DEPTH) {
    if ((st = jnd_image_alloc(&f.depth, w, h, 1))) goto fail;
    static const int d[1] = {0};
    read_back(r, r->aux_fbo, GL_COLOR_ATTACHMENT1, d, 1, &f.depth);
  }
  if (outs & JND_OUT_MOTION) {
    if ((st = jnd_image_alloc(&f.motion, w, h, 2))) goto fail;
    static const int mv[2] = {1, 2};
    read_back(r, r->aux_fbo, GL_COLOR_ATTACHMENT1, mv, 2, &f.motion);
  }
  if (outs & JND_OUT_MIP) {
    if ((st = jnd_image_alloc(&f.mip, w, h, JND_MAP_SLOTS))) goto fail;
    jnd_image four = {w, h, 4, f.mip.data}, one = {w, h, 1, f.mip.data + (size_t)4 * w * h};
    static const int m4[4] = {0, 1, 2, 3}, m1[1] = {0};
    read_back(r, r->aux_fbo, GL_COLOR_ATTACHMENT2, m4, 4, &four);
    read_back(r, r->aux_fbo, GL_COLOR_ATTACHMENT3, m1, 1, &one);
    if ((st = jnd_image_alloc(&f.material, w, h, 1))) goto fail;
    static const int mat[1] = {1};
    read_back(r, r->aux_fbo, GL_COLOR_ATTACHMENT3, mat, 1, &f.material);
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  if ((st = gl_check("read-back"))) goto fail;
  *frame = f;
  return JND_OK;
fail:
  jnd_frame_free(&f);
  return st;
}

/* ---- re-rendering some materials of a view (the judge's partial renders) ----
 *
 * A candidate that changes only texture maps changes only the samples of the
 * materials using them; depth, coverage and every other material's samples
 * are the reference's. So the reference's multisampled depth is kept, and a
 * re-render restores it, clears colour to zero and draws only the changed
 * materials with the depth test GL_EQUAL: exactly their visible samples are
 * shaded, with the same fragments (same primitives, same derivatives) as in
 * a full render. Resolving averages samples linearly, so the full rendering
 * is the reference minus these materials' resolved samples under the old
 * maps plus those under the new ones (docs/render.md). Blended materials and
 * alpha-masked coverage changes break this; the caller falls back to a full
 * rendering then. */

jnd_status jnd_render_keep_depth(jnd_renderer *r, unsigned *handle) {
  jnd_gl_use(&r->gl);
  GLuint rb = 0;
  glCreateRenderbuffers(1, &rb);
  glNamedRenderbufferStorageMultisample(rb, r->samples, GL_DEPTH_COMPONENT32F, r->w, r->h);
  glCopyImageSubData(r->msaa_depth, GL_RENDERBUFFER, 0, 0, 0, 0, rb, GL_RENDERBUFFER, 0, 0, 0, 0, r->w, r->h, 1);
  jnd_status st = gl_check("keeping the depth of a rendering");
  if (st) {
    glDeleteRenderbuffers(1, &rb);
    return st;
  }
  *handle = rb;
  return JND_OK;
}

void jnd_render_drop_depth(jnd_renderer *r, unsigned handle) {
  if (r && handle) {
    jnd_gl_use(&r->gl);
    GLuint rb = handle;
    glDeleteRenderbuffers(1, &rb);
  }
}

jnd_status jnd_render_materials(jnd_renderer *r, const jnd_scene *scene, const jnd_view *view, unsigned depth,
                                const unsigned char *only, int x0, int y0, int w, int h, jnd_image *out) {
  memset(out, 0, sizeof *out);
  if (x0 < 0 || y0 < 0 || w < 1 || h < 1 || x0 + w > r->w || y0 + h > r->h)
    return jnd_fail(JND_ERR_ARG, "render: rectangle %d,%d %d × %d outside the %d × %d image", x0, y0, w, h, r->w, r->h);
  double vp[16];
  jnd_status st = setup_view(r, scene, view, vp);
  if (st) return st;
  int gy = r->h - y0 - h;   /* GL rows count from the bottom */
  glBindFramebuffer(GL_FRAMEBUFFER, r->msaa_fbo);
  glEnable(GL_MULTISAMPLE);
  multisample_shading(r);
  glCopyImageSubData((GLuint)depth, GL_RENDERBUFFER, 0, x0, gy, 0, r->msaa_depth, GL_RENDERBUFFER, 0, x0, gy, 0, w, h, 1);
  glEnable(GL_SCISSOR_TEST);
  glScissor(x0, gy, w, h);
  const float zero[4] = {0, 0, 0, 0};
  glClearNamedFramebufferfv(r->msaa_fbo, GL_COLOR, 0, zero);
  glDepthFunc(GL_EQUAL);
  glDepthMask(GL_FALSE);
  draw_meshes(r, scene, view->camera.eye, view->unlit ? 2 : 0, only);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  glBlitNamedFramebuffer(r->msaa_fbo, r->resolve_fbo, x0, gy, x0 + w, gy + h, x0, gy, x0 + w, gy + h,
                         GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glDisable(GL_SCISSOR_TEST);
  if ((st = gl_check("partial colour pass"))) return st;
  if ((st = jnd_image_alloc(out, w, h, 4))) return st;
  glNamedFramebufferReadBuffer(r->resolve_fbo, GL_COLOR_ATTACHMENT0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, r->resolve_fbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(x0, gy, w, h, GL_RGBA, GL_FLOAT, r->readbuf);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  size_t P = (size_t)w * h;
  for (int c = 0; c < 4; c++)
    for (int y = 0; y < h; y++) {
      const float *row = r->readbuf + (size_t)(h - 1 - y) * w * 4;
      float *d = out->data + c * P + (size_t)y * w;
      for (int x = 0; x < w; x++) d[x] = row[x * 4 + c];
    }
  if ((st = gl_check("partial read-back"))) jnd_image_free(out);
  return st;
}

void jnd_frame_free(jnd_frame *f) {
  jnd_image_free(&f->color);
  jnd_image_free(&f->depth);
  jnd_image_free(&f->mask);
  jnd_image_free(&f->motion);
  jnd_image_free(&f->mip);
  jnd_image_free(&f->material);
}

/* the curve over a span, vectorised (each sample as jnd_srgb_encode gives
 * it: no contraction, no reordering) */
JND_HOT static void srgb_encode_span(const float *restrict in, float *restrict out, size_t n) {
#pragma omp simd
  for (size_t i = 0; i < n; i++) out[i] = jnd_srgb_encode(in[i]);
}

jnd_status jnd_render_to_srgb(const jnd_image *linear, jnd_image *out) {
  jnd_status st = jnd_image_alloc(out, linear->w, linear->h, linear->c);
  if (st) return st;
  srgb_encode_span(linear->data, out->data, (size_t)linear->w * linear->h * linear->c);
  return JND_OK;
}
