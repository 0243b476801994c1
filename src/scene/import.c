/* Asset import through assimp's C API: glTF 2.0 (.gltf, .glb) and OBJ + MTL
 * become meshes in object units and metallic-roughness materials. */
#include <assimp/GltfMaterial.h>
#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "core/core.h"
#include "io/io.h"
#include "scene/scene.h"

#define MAX_MODEL_BYTES ((size_t)1 << 31)
#define MAX_TEXTURE_BYTES ((size_t)1 << 28)

/* assimp messages can span lines; ours are one line. */
static void one_line(char *s) {
  for (; *s; s++)
    if (*s == '\n' || *s == '\r') *s = ' ';
}

static jnd_status decode_blob(const char *name, const unsigned char *buf, size_t n, jnd_image *out) {
  jnd_image_info info;
  if (n >= 8 && memcmp(buf, "\x89PNG", 4) == 0) return jnd_decode_png(name, buf, n, out, &info);
  if (n >= 3 && buf[0] == 0xFF && buf[1] == 0xD8) return jnd_decode_jpeg(name, buf, n, out, &info);
  return jnd_fail(JND_ERR_FORMAT, "%s: not a PNG or JPEG image", name);
}

/* Loads the image a material refers to: "*N" for an embedded texture, else a
 * path relative to the model's folder. */
static jnd_status load_texture(const struct aiScene *sc, const char *model, const char *ref,
                               jnd_image *out, char *desc, size_t ndesc) {
  if (ref[0] == '*') {
    char *end;
    long k = strtol(ref + 1, &end, 10);
    snprintf(desc, ndesc, "%s: embedded texture %s", model, ref);
    if (*end || k < 0 || k >= (long)sc->mNumTextures)
      return jnd_fail(JND_ERR_FORMAT, "%s: embedded texture %s does not exist", model, ref);
    const struct aiTexture *t = sc->mTextures[k];
    if (t->mHeight == 0)
      return decode_blob(desc, (const unsigned char *)t->pcData, t->mWidth, out);
    jnd_status st = jnd_image_alloc(out, (int)t->mWidth, (int)t->mHeight, 4);
    if (st) return st;
    size_t plane = (size_t)t->mWidth * t->mHeight;
    for (size_t i = 0; i < plane; i++) {
      out->data[i] = t->pcData[i].r / 255.0f;
      out->data[plane + i] = t->pcData[i].g / 255.0f;
      out->data[2 * plane + i] = t->pcData[i].b / 255.0f;
      out->data[3 * plane + i] = t->pcData[i].a / 255.0f;
    }
    return JND_OK;
  }
  char full[2048];
  jnd_model_relative(model, ref, 1, full, sizeof full);
  snprintf(desc, ndesc, "%s", full);
  unsigned char *buf = NULL;
  size_t n = 0;
  jnd_status st = jnd_read_file(full, MAX_TEXTURE_BYTES, &buf, &n);
  if (st) return st;
  st = decode_blob(full, buf, n, out);
  free(buf);
  return st;
}

static float get_float(const struct aiMaterial *m, const char *key, unsigned type, unsigned idx,
                       float dflt, int *found) {
  ai_real v;
  unsigned int one = 1;
  if (aiGetMaterialFloatArray(m, key, type, idx, &v, &one) == aiReturn_SUCCESS && one == 1) {
    if (found) *found = 1;
    return (float)v;
  }
  if (found) *found = 0;
  return dflt;
}

/* glTF's KHR_texture_transform (offset o, rotation r, scale s), as its
 * extension text defines it: uv' = T(o) R(r) S(s) uv with R = [cos −sin;
 * sin cos] on (u, v). assimp 5.2 (glTF2Importer) stores it re-expressed for
 * its own uv convention — rotation about (0.5, 0.5), v flipped — and
 * aiProcess_FlipUVs then negates the rotation and the v translation back:
 *   rotation = r, scaling = s,
 *   translation.x = s_x/2 (1 − cos r + sin r) + o_x,
 *   translation.y = o_y − s_y/2 (sin r + cos r − 1) − 1 + s_y.
 * Undone here into the affine map on our (glTF-convention) uvs.
 * tests/unit/test_render.c renders a transformed quad against the same quad
 * with the transform applied to its uvs, so a change of assimp's convention
 * shows. */
static int uv_transform_from_assimp(const struct aiUVTransform *t, float xf[6]) {
  double r = t->mRotation, sx = t->mScaling.x, sy = t->mScaling.y, c = cos(r), sn = sin(r);
  double ox = t->mTranslation.x - 0.5 * sx * (1.0 - c + sn);
  double oy = t->mTranslation.y + 0.5 * sy * (sn + c - 1.0) + 1.0 - sy;
  double m[6] = {c * sx, -sn * sy, ox, sn * sx, c * sy, oy};
  for (int k = 0; k < 6; k++) {
    if (!isfinite(m[k])) return 0;
    xf[k] = (float)m[k];
  }
  return 1;
}

/* One slot: the first texture of the listed assimp types that exists. */
static void import_slot(jnd_scene *s, const struct aiScene *sc, const struct aiMaterial *am, int mi,
                        jnd_map_slot slot, const enum aiTextureType *types, int ntypes, int gltf) {
  for (int t = 0; t < ntypes; t++) {
    if (aiGetMaterialTextureCount(am, types[t]) == 0) continue;
    struct aiString path;
    enum aiTextureMapping mapping;
    unsigned int uv = 0;
    enum aiTextureMapMode mode[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
    if (aiGetMaterialTexture(am, types[t], 0, &path, &mapping, &uv, NULL, NULL, mode, NULL) !=
        aiReturn_SUCCESS)
      continue;
    jnd_image img = {0};
    char desc[2100];
    if (load_texture(sc, s->path, path.data, &img, desc, sizeof desc) != JND_OK) {
      char msg[1024];
      snprintf(msg, sizeof msg, "%s", jnd_last_error());
      one_line(msg);
      jnd_scene_add_warning(s, "%s: %s/%s: texture not loaded (%s); using the factor",
                            s->path, s->materials[mi].name, jnd_map_slot_name(slot), msg);
      return;
    }
    int k = jnd_scene_add_map(s, mi, slot, &img);
    if (k < 0) return;
    jnd_map *m = &s->maps[k];
    /* one image of the file, however many slots sample it: the same
     * embedded image ("*N"), or the same file however its path is spelt
     * ("a.png", "./a.png", a link to it: its device and inode) */
    struct stat fs;
    char id[64];
    const char *key = path.data;
    if (path.data[0] != '*' && stat(desc, &fs) == 0) {   /* desc: the file's path as read */
      snprintf(id, sizeof id, "file %llu:%llu", (unsigned long long)fs.st_dev, (unsigned long long)fs.st_ino);
      key = id;
    }
    m->source = strdup(key);
    for (int j = 0; j < k && m->source; j++)
      if (s->maps[j].source && strcmp(s->maps[j].source, m->source) == 0) {
        m->image = s->maps[j].image;
        break;
      }
    m->uv_set = uv == 1 ? 1 : 0;
    if (uv > 1)
      jnd_scene_add_warning(s, "%s: %s/%s: texture coordinate set %u not supported; using 0",
                            s->path, s->materials[mi].name, jnd_map_slot_name(slot), uv);
    jnd_wrap w[2];
    for (int a = 0; a < 2; a++)
      w[a] = mode[a] == aiTextureMapMode_Clamp   ? JND_WRAP_CLAMP
             : mode[a] == aiTextureMapMode_Mirror ? JND_WRAP_MIRROR
                                                  : JND_WRAP_REPEAT;
    m->wrap_s = w[0];
    m->wrap_t = w[1];
    int mag = 0, min = 0;
    if (aiGetMaterialIntegerArray(am, _AI_MATKEY_GLTF_MAPPINGFILTER_MAG_BASE, types[t], 0, &mag, NULL) ==
        aiReturn_SUCCESS)
      m->mag_nearest = mag == 9728;                                   /* GL_NEAREST */
    if (aiGetMaterialIntegerArray(am, _AI_MATKEY_GLTF_MAPPINGFILTER_MIN_BASE, types[t], 0, &min, NULL) ==
        aiReturn_SUCCESS)
      m->min_nearest = min == 9728 || min == 9984 || min == 9986;    /* NEAREST* */
    struct aiUVTransform uvt;
    unsigned int nf = sizeof uvt / sizeof(ai_real);
    if (aiGetMaterialFloatArray(am, _AI_MATKEY_UVTRANSFORM_BASE, types[t], 0, (ai_real *)&uvt, &nf) ==
            aiReturn_SUCCESS && nf == sizeof uvt / sizeof(ai_real)) {
      int identity = uvt.mRotation == 0 && uvt.mScaling.x == 1 && uvt.mScaling.y == 1 && uvt.mTranslation.x == 0 &&
                     uvt.mTranslation.y == 0;
      if (gltf && !uv_transform_from_assimp(&uvt, m->uvxf))
        jnd_scene_add_warning(s, "%s: %s/%s: texture transform is not finite; ignored", s->path,
                              s->materials[mi].name, jnd_map_slot_name(slot));
      else if (!gltf && !identity)
        jnd_scene_add_warning(s, "%s: %s/%s: texture transform of this format not supported; ignored", s->path,
                              s->materials[mi].name, jnd_map_slot_name(slot));
    }
    return;
  }
}

/* with_maps 0: the material's factors and name only (a level of detail's
 * materials are the base's; only their names are matched) */
static void import_material(jnd_scene *s, const struct aiScene *sc, int mi, int with_maps) {
  const struct aiMaterial *am = sc->mMaterials[mi];
  jnd_material *m = &s->materials[mi];
  struct aiString name;
  char nm[96] = "";
  if (aiGetMaterialString(am, AI_MATKEY_NAME, &name) == aiReturn_SUCCESS)
    snprintf(nm, sizeof nm, "%.80s", name.data);
  if (!nm[0]) snprintf(nm, sizeof nm, "material%d", mi);
  for (char *p = nm; *p; p++)   /* keep "MATERIAL/SLOT" addressable */
    if (*p == '/' || *p == '=' || *p == '\n' || *p == ',') *p = '_';
  /* repeated names get "#N" */
  int dup = 0;
  for (int j = 0; j < mi; j++)
    if (strncmp(s->materials[j].name, nm, strlen(nm)) == 0 &&
        (s->materials[j].name[strlen(nm)] == 0 || s->materials[j].name[strlen(nm)] == '#'))
      dup++;
  jnd_material_defaults(m, nm);
  if (dup) snprintf(m->name, sizeof m->name, "%.80s#%d", nm, dup + 1);

  int gltf = 0;
  m->metallic = get_float(am, AI_MATKEY_METALLIC_FACTOR, 1.0f, &gltf);
  struct aiColor4D c;
  if (gltf) {
    m->roughness = get_float(am, AI_MATKEY_ROUGHNESS_FACTOR, 1.0f, NULL);
    if (aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &c) == aiReturn_SUCCESS) {
      m->base_color[0] = c.r;
      m->base_color[1] = c.g;
      m->base_color[2] = c.b;
      m->base_color[3] = c.a;
    } else if (aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS) {
      m->base_color[0] = c.r;
      m->base_color[1] = c.g;
      m->base_color[2] = c.b;
      m->base_color[3] = c.a;
    }
  } else {
    /* OBJ/MTL: Kd is the base colour, d the opacity, Ns the Phong exponent;
     * a Phong lobe of exponent n matches a microfacet roughness α with
     * α² = 2 / (n + 2), and glTF's roughness is √α. */
    m->metallic = 0;
    if (aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS) {
      m->base_color[0] = c.r;
      m->base_color[1] = c.g;
      m->base_color[2] = c.b;
    }
    m->base_color[3] = get_float(am, AI_MATKEY_OPACITY, 1.0f, NULL);
    float ns = get_float(am, AI_MATKEY_SHININESS, 0.0f, NULL);
    m->roughness = (float)jnd_clampd(pow(2.0 / (ns + 2.0), 0.25), 0.05, 1.0);
    if (m->base_color[3] < 1) m->alpha_mode = JND_ALPHA_BLEND;
  }
  if (aiGetMaterialColor(am, AI_MATKEY_COLOR_EMISSIVE, &c) == aiReturn_SUCCESS) {
    m->emissive[0] = c.r;
    m->emissive[1] = c.g;
    m->emissive[2] = c.b;
  }
  struct aiString mode;
  if (aiGetMaterialString(am, AI_MATKEY_GLTF_ALPHAMODE, &mode) == aiReturn_SUCCESS) {
    if (strcmp(mode.data, "MASK") == 0) m->alpha_mode = JND_ALPHA_MASK;
    else if (strcmp(mode.data, "BLEND") == 0) m->alpha_mode = JND_ALPHA_BLEND;
    else m->alpha_mode = JND_ALPHA_OPAQUE;
  }
  m->alpha_cutoff = get_float(am, AI_MATKEY_GLTF_ALPHACUTOFF, 0.5f, NULL);
  int two = 0;
  if (aiGetMaterialIntegerArray(am, AI_MATKEY_TWOSIDED, &two, NULL) == aiReturn_SUCCESS) m->double_sided = two != 0;
  m->normal_scale = get_float(am, _AI_MATKEY_GLTF_SCALE_BASE, aiTextureType_NORMALS, 0, 1.0f, NULL);
  m->occlusion_strength =
      get_float(am, _AI_MATKEY_GLTF_STRENGTH_BASE, aiTextureType_LIGHTMAP, 0, 1.0f, NULL);

  static const enum aiTextureType base[] = {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE};
  static const enum aiTextureType mr[] = {aiTextureType_UNKNOWN, aiTextureType_METALNESS,
                                          aiTextureType_DIFFUSE_ROUGHNESS};
  static const enum aiTextureType nrm[] = {aiTextureType_NORMALS, aiTextureType_NORMAL_CAMERA};
  static const enum aiTextureType occ[] = {aiTextureType_LIGHTMAP, aiTextureType_AMBIENT_OCCLUSION};
  static const enum aiTextureType emi[] = {aiTextureType_EMISSIVE, aiTextureType_EMISSION_COLOR};
  if (!with_maps) return;
  import_slot(s, sc, am, mi, JND_MAP_BASE_COLOR, base, 2, gltf);
  if (gltf) import_slot(s, sc, am, mi, JND_MAP_METALLIC_ROUGHNESS, mr, 3, gltf);
  import_slot(s, sc, am, mi, JND_MAP_NORMAL, nrm, 2, gltf);
  import_slot(s, sc, am, mi, JND_MAP_OCCLUSION, occ, 2, gltf);
  import_slot(s, sc, am, mi, JND_MAP_EMISSIVE, emi, 2, gltf);
  if (!gltf && aiGetMaterialTextureCount(am, aiTextureType_HEIGHT) > 0 && m->map[JND_MAP_NORMAL] < 0)
    jnd_scene_add_warning(s, "%s: %s: bump (height) maps are not used; give a normal map (norm)",
                          s->path, m->name);
}

static jnd_status import_mesh(jnd_scene *s, const struct aiMesh *am, jnd_mesh *out) {
  size_t nt = 0;
  for (unsigned f = 0; f < am->mNumFaces; f++)
    if (am->mFaces[f].mNumIndices == 3) nt++;
  out->material = (int)am->mMaterialIndex;
  out->nverts = am->mNumVertices;
  out->ntris = nt;
  /* zeroed: what the file lacks (normals, tangents, uvs) must not be the
   * allocator's leftovers (garbage uvs made split_mirrored_vertices
   * duplicate vertices at random) */
  out->vertices = jnd_calloc(out->nverts, JND_VTX_FLOATS * sizeof(float));
  out->indices = jnd_alloc(nt * 3, sizeof(uint32_t));
  if (!out->vertices || !out->indices) return JND_ERR_NOMEM;
  size_t t = 0;
  for (unsigned f = 0; f < am->mNumFaces; f++) {
    const struct aiFace *fc = &am->mFaces[f];
    if (fc->mNumIndices != 3) continue;
    for (int k = 0; k < 3; k++) {
      if (fc->mIndices[k] >= am->mNumVertices)
        return jnd_fail(JND_ERR_FORMAT, "%s: vertex index out of range", s->path);
      out->indices[3 * t + k] = fc->mIndices[k];
    }
    t++;
  }
  int has_tangents = am->mTangents && am->mBitangents && am->mNormals;
  for (unsigned v = 0; v < am->mNumVertices; v++) {
    float *d = out->vertices + (size_t)v * JND_VTX_FLOATS;
    d[0] = am->mVertices[v].x;
    d[1] = am->mVertices[v].y;
    d[2] = am->mVertices[v].z;
    for (int k = 0; k < 3; k++)
      if (!isfinite(d[k])) return jnd_fail(JND_ERR_FORMAT, "%s: vertex positions are not finite", s->path);
    if (am->mNormals) {
      d[3] = am->mNormals[v].x;
      d[4] = am->mNormals[v].y;
      d[5] = am->mNormals[v].z;
      float l = sqrtf(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
      if (!(l > 1e-12f) || !isfinite(l)) {
        d[3] = d[5] = 0;
        d[4] = 1;
      } else {
        for (int k = 3; k < 6; k++) d[k] /= l;
      }
    } else {
      d[4] = 1;
    }
    if (has_tangents) {
      struct aiVector3D n = am->mNormals[v], tg = am->mTangents[v], b = am->mBitangents[v];
      d[6] = tg.x;
      d[7] = tg.y;
      d[8] = tg.z;
      float cx = n.y * tg.z - n.z * tg.y, cy = n.z * tg.x - n.x * tg.z, cz = n.x * tg.y - n.y * tg.x;
      d[9] = cx * b.x + cy * b.y + cz * b.z < 0 ? -1.0f : 1.0f;
    }
    for (int set = 0; set < 2; set++)
      if (am->mTextureCoords[set]) {
        d[10 + 2 * set] = am->mTextureCoords[set][v].x;
        d[11 + 2 * set] = am->mTextureCoords[set][v].y;
      }
    if (am->mColors[0]) {
      d[14] = am->mColors[0][v].r;
      d[15] = am->mColors[0][v].g;
      d[16] = am->mColors[0][v].b;
      d[17] = am->mColors[0][v].a;
    } else {
      d[14] = d[15] = d[16] = d[17] = 1;
    }
    for (int k = 3; k < JND_VTX_FLOATS; k++)
      if (!isfinite(d[k])) d[k] = 0;
  }
  int tangents_ok = has_tangents;
  for (unsigned v = 0; tangents_ok && v < am->mNumVertices; v++) {
    const float *d = out->vertices + (size_t)v * JND_VTX_FLOATS;
    if (!(d[6] * d[6] + d[7] * d[7] + d[8] * d[8] > 1e-12f)) tangents_ok = 0;
  }
  if (!tangents_ok) jnd_mesh_compute_tangents(out);
  return JND_OK;
}

/* ---- assimp reading a file whose bytes we give (a variant of a glTF with
 * MSFT_lod), every other file (buffers) from disk ---- */

typedef struct {
  const char *path;              /* the file served from memory */
  const unsigned char *data;
  size_t n;
} mem_io;

typedef struct {
  FILE *f;                       /* a file on disk, or NULL */
  const unsigned char *data;     /* the memory file */
  size_t n, pos;
} io_file;

static size_t io_read(struct aiFile *af, char *buf, size_t size, size_t count) {
  io_file *f = (io_file *)af->UserData;
  if (size == 0 || count == 0) return 0;
  if (f->f) return fread(buf, size, count, f->f);
  size_t want = size * count, left = f->n - f->pos;
  if (count > SIZE_MAX / size) want = SIZE_MAX;
  size_t got = want < left ? want : left;
  got -= got % size;
  memcpy(buf, f->data + f->pos, got);
  f->pos += got;
  return got / size;
}

static size_t io_write(struct aiFile *af, const char *buf, size_t size, size_t count) { return 0; }

static size_t io_tell(struct aiFile *af) {
  io_file *f = (io_file *)af->UserData;
  if (f->f) {
    long p = ftell(f->f);
    return p < 0 ? 0 : (size_t)p;
  }
  return f->pos;
}

static size_t io_size(struct aiFile *af) {
  io_file *f = (io_file *)af->UserData;
  if (f->f) {
    long p = ftell(f->f), e = -1;
    if (p >= 0 && fseek(f->f, 0, SEEK_END) == 0) e = ftell(f->f);
    if (p >= 0) fseek(f->f, p, SEEK_SET);
    return e < 0 ? 0 : (size_t)e;
  }
  return f->n;
}

static enum aiReturn io_seek(struct aiFile *af, size_t off, enum aiOrigin origin) {
  io_file *f = (io_file *)af->UserData;
  if (f->f) {
    int w = origin == aiOrigin_SET ? SEEK_SET : origin == aiOrigin_CUR ? SEEK_CUR : SEEK_END;
    return fseek(f->f, (long)off, w) == 0 ? aiReturn_SUCCESS : aiReturn_FAILURE;
  }
  size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? f->pos : f->n;
  if (off > f->n - base) return aiReturn_FAILURE;
  f->pos = base + off;
  return aiReturn_SUCCESS;
}

static void io_flush(struct aiFile *af) {}

static struct aiFile *io_open(struct aiFileIO *io, const char *path, const char *mode) {
  const mem_io *m = (const mem_io *)io->UserData;
  if (strchr(mode, 'w') || strchr(mode, 'a')) return NULL;
  io_file *f = calloc(1, sizeof *f);
  struct aiFile *af = calloc(1, sizeof *af);
  if (!f || !af) {
    free(f);
    free(af);
    return NULL;
  }
  if (strcmp(path, m->path) == 0) {
    f->data = m->data;
    f->n = m->n;
  } else if (!(f->f = fopen(path, "rb"))) {
    free(f);
    free(af);
    return NULL;
  }
  af->ReadProc = io_read;
  af->WriteProc = io_write;
  af->TellProc = io_tell;
  af->FileSizeProc = io_size;
  af->SeekProc = io_seek;
  af->FlushProc = io_flush;
  af->UserData = (aiUserData)f;
  return af;
}

static void io_close(struct aiFileIO *io, struct aiFile *af) {
  if (!af) return;
  io_file *f = (io_file *)af->UserData;
  if (f && f->f) fclose(f->f);
  free(f);
  free(af);
}

/* Imports path with assimp (its bytes from data when not NULL) into a scene;
 * with_maps 0 skips the texture maps. */
static jnd_status load_scene(const char *path, const unsigned char *data, size_t ndata, int with_maps,
                             jnd_scene **out) {
  *out = NULL;
  /* validated first, the rest after a look at the positions: joining
   * vertices would merge a NaN position into another and hide it */
  unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals |
                   aiProcess_PreTransformVertices | aiProcess_SortByPType | aiProcess_FlipUVs;
  const struct aiScene *sc;
  if (data) {
    mem_io m = {path, data, ndata};
    struct aiFileIO io = {io_open, io_close, (aiUserData)&m};
    sc = aiImportFileEx(path, aiProcess_ValidateDataStructure, &io);
  } else {
    sc = aiImportFile(path, aiProcess_ValidateDataStructure);
  }
  for (unsigned i = 0; sc && i < sc->mNumMeshes; i++)
    for (unsigned v = 0; v < sc->mMeshes[i]->mNumVertices; v++) {
      const struct aiVector3D *q = &sc->mMeshes[i]->mVertices[v];
      if (!isfinite(q->x) || !isfinite(q->y) || !isfinite(q->z)) {
        aiReleaseImport(sc);
        return jnd_fail(JND_ERR_FORMAT, "%s: vertex positions are not finite", path);
      }
    }
  if (sc) sc = aiApplyPostProcessing(sc, flags);
  if (!sc) {
    char msg[512];
    snprintf(msg, sizeof msg, "%s", aiGetErrorString());
    one_line(msg);
    return jnd_fail(JND_ERR_FORMAT, "%s: cannot import (%s)", path, msg[0] ? msg : "unknown format");
  }
  jnd_status st = JND_OK;
  jnd_scene *s = jnd_scene_new(path);
  if (!s) {
    aiReleaseImport(sc);
    return JND_ERR_NOMEM;
  }
  if (sc->mFlags & AI_SCENE_FLAGS_INCOMPLETE) {
    st = jnd_fail(JND_ERR_FORMAT, "%s: the file is incomplete", path);
    goto done;
  }
  s->nmaterials = (int)sc->mNumMaterials;
  s->materials = jnd_calloc(s->nmaterials ? (size_t)s->nmaterials : 1, sizeof *s->materials);
  s->meshes = jnd_calloc(sc->mNumMeshes ? sc->mNumMeshes : 1, sizeof *s->meshes);
  if (!s->materials || !s->meshes) {
    st = JND_ERR_NOMEM;
    goto done;
  }
  for (int i = 0; i < s->nmaterials; i++) import_material(s, sc, i, with_maps);
  for (unsigned i = 0; i < sc->mNumMeshes; i++) {
    const struct aiMesh *am = sc->mMeshes[i];
    if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    if (am->mMaterialIndex >= sc->mNumMaterials) {
      st = jnd_fail(JND_ERR_FORMAT, "%s: mesh %u refers to a missing material", path, i);
      goto done;
    }
    jnd_mesh *m = &s->meshes[s->nmeshes++];
    if ((st = import_mesh(s, am, m))) goto done;
    if (m->ntris == 0) {
      free(m->vertices);
      free(m->indices);
      s->nmeshes--;
    }
  }
  if (s->nmeshes == 0) {
    st = jnd_fail(JND_ERR_FORMAT, "%s: no triangles to render", path);
    goto done;
  }
  jnd_scene_compute_bounds(s);
done:
  aiReleaseImport(sc);
  if (st) {
    if (st == JND_ERR_NOMEM) jnd_fail(st, "%s: out of memory", path);
    jnd_scene_free(s);
    return st;
  }
  *out = s;
  return JND_OK;
}

jnd_status jnd_scene_load(const char *path, jnd_scene **out) {
  *out = NULL;
  struct stat stt;
  if (stat(path, &stt) != 0) return jnd_fail(JND_ERR_IO, "%s: no such file", path);
  if (!S_ISREG(stt.st_mode)) return jnd_fail(JND_ERR_IO, "%s: not a regular file", path);
  if ((size_t)stt.st_size > MAX_MODEL_BYTES) return jnd_fail(JND_ERR_LIMIT, "%s: file too large", path);
  if (stt.st_size == 0) return jnd_fail(JND_ERR_FORMAT, "%s: the file is empty", path);
  const char *ext = strrchr(path, '.');
  if (!ext || (strcasecmp(ext, ".gltf") != 0 && strcasecmp(ext, ".glb") != 0)) return load_scene(path, NULL, 0, 1, out);
  /* glTF: levels of detail as MSFT_lod nodes? */
  unsigned char *file = NULL;
  size_t n = 0;
  jnd_status st = jnd_read_file(path, MAX_MODEL_BYTES, &file, &n);
  if (st) return st;
  int levels = 1;
  if (strcasecmp(ext, ".glb") == 0 && (n < 4 || memcmp(file, "glTF", 4) != 0))
    st = jnd_fail(JND_ERR_FORMAT, "%s: GLB parse error: it does not start with a glTF binary header ('glTF')", path);
  else
    st = jnd_gltf_lod_variant(path, file, n, 0, &levels, NULL, NULL);
  if (st || levels < 2) {
    free(file);
    /* a file that is no glTF (its container or JSON broken) is not handed to assimp, whose other readers
     * would guess another format by content (a corrupt GLB once read as "OBJ: Invalid face index") */
    return st ? st : load_scene(path, NULL, 0, 1, out);
  }
  jnd_scene *s = NULL;
  for (int k = 0; k < levels && !st; k++) {
    unsigned char *var = NULL;
    size_t vn = 0;
    jnd_scene *lk = NULL;
    st = jnd_gltf_lod_variant(path, file, n, k, &levels, &var, &vn);
    if (!st) st = load_scene(path, var, vn, k == 0, &lk);
    free(var);
    if (st) break;
    if (k == 0) {
      s = lk;
    } else {
      char src[1100];
      snprintf(src, sizeof src, "%s#MSFT_lod %d", path, k);
      st = jnd_scene_lod_add(s, lk, src);
    }
  }
  free(file);
  if (st) {
    jnd_scene_free(s);
    return st;
  }
  *out = s;
  return JND_OK;
}
