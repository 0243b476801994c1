/* assimp opened when a command first imports a model (core.h,
 * jnd_lazy_symbol): the functions of assimp's C API that import.c calls,
 * with assimp's prototypes, each forwarding to the library's own. Built
 * where CMake read assimp's soname (JND_ASSIMP_SONAME); elsewhere jnd links
 * assimp as before and this file is empty. Where the library cannot be
 * opened, an import fails as assimp's own failures do: no scene, and
 * aiGetErrorString says why. */
#ifdef JND_ASSIMP_SONAME
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <stdatomic.h>

#include "core/core.h"

static jnd_lazy_lib assimp = {JND_ASSIMP_SONAME, NULL};

const struct aiScene *aiImportFile(const char *pFile, unsigned int pFlags) {
  JND_LAZY_FN(&assimp, const struct aiScene *(*)(const char *, unsigned int), aiImportFile);
  return f ? f(pFile, pFlags) : NULL;
}

const struct aiScene *aiImportFileEx(const char *pFile, unsigned int pFlags, struct aiFileIO *pFS) {
  JND_LAZY_FN(&assimp, const struct aiScene *(*)(const char *, unsigned int, struct aiFileIO *), aiImportFileEx);
  return f ? f(pFile, pFlags, pFS) : NULL;
}

const struct aiScene *aiApplyPostProcessing(const struct aiScene *pScene, unsigned int pFlags) {
  JND_LAZY_FN(&assimp, const struct aiScene *(*)(const struct aiScene *, unsigned int), aiApplyPostProcessing);
  return f ? f(pScene, pFlags) : NULL;
}

void aiReleaseImport(const struct aiScene *pScene) {
  JND_LAZY_FN(&assimp, void (*)(const struct aiScene *), aiReleaseImport);
  if (f) f(pScene);
}

const char *aiGetErrorString(void) {
  JND_LAZY_FN(&assimp, const char *(*)(void), aiGetErrorString);
  return f ? f() : jnd_last_error(); /* the loader's message */
}

enum aiReturn aiGetMaterialColor(const struct aiMaterial *pMat, const char *pKey, unsigned int type,
                                 unsigned int index, struct aiColor4D *pOut) {
  JND_LAZY_FN(&assimp, enum aiReturn (*)(const struct aiMaterial *, const char *, unsigned, unsigned, struct aiColor4D *),
            aiGetMaterialColor);
  return f ? f(pMat, pKey, type, index, pOut) : aiReturn_FAILURE;
}

enum aiReturn aiGetMaterialFloatArray(const struct aiMaterial *pMat, const char *pKey, unsigned int type,
                                      unsigned int index, ai_real *pOut, unsigned int *pMax) {
  JND_LAZY_FN(&assimp, enum aiReturn (*)(const struct aiMaterial *, const char *, unsigned, unsigned, ai_real *, unsigned *),
            aiGetMaterialFloatArray);
  return f ? f(pMat, pKey, type, index, pOut, pMax) : aiReturn_FAILURE;
}

enum aiReturn aiGetMaterialIntegerArray(const struct aiMaterial *pMat, const char *pKey, unsigned int type,
                                        unsigned int index, int *pOut, unsigned int *pMax) {
  JND_LAZY_FN(&assimp, enum aiReturn (*)(const struct aiMaterial *, const char *, unsigned, unsigned, int *, unsigned *),
            aiGetMaterialIntegerArray);
  return f ? f(pMat, pKey, type, index, pOut, pMax) : aiReturn_FAILURE;
}

enum aiReturn aiGetMaterialString(const struct aiMaterial *pMat, const char *pKey, unsigned int type,
                                  unsigned int index, struct aiString *pOut) {
  JND_LAZY_FN(&assimp, enum aiReturn (*)(const struct aiMaterial *, const char *, unsigned, unsigned, struct aiString *),
            aiGetMaterialString);
  return f ? f(pMat, pKey, type, index, pOut) : aiReturn_FAILURE;
}

unsigned int aiGetMaterialTextureCount(const struct aiMaterial *pMat, enum aiTextureType type) {
  JND_LAZY_FN(&assimp, unsigned (*)(const struct aiMaterial *, enum aiTextureType), aiGetMaterialTextureCount);
  return f ? f(pMat, type) : 0;
}

enum aiReturn aiGetMaterialTexture(const struct aiMaterial *mat, enum aiTextureType type, unsigned int index,
                                   struct aiString *path, enum aiTextureMapping *mapping, unsigned int *uvindex,
                                   ai_real *blend, enum aiTextureOp *op, enum aiTextureMapMode *mapmode,
                                   unsigned int *flags) {
  JND_LAZY_FN(&assimp, enum aiReturn (*)(const struct aiMaterial *, enum aiTextureType, unsigned, struct aiString *,
                              enum aiTextureMapping *, unsigned *, ai_real *, enum aiTextureOp *,
                              enum aiTextureMapMode *, unsigned *),
            aiGetMaterialTexture);
  return f ? f(mat, type, index, path, mapping, uvindex, blend, op, mapmode, flags) : aiReturn_FAILURE;
}
#else
typedef int jnd_assimp_linked; /* ISO C wants a declaration in every file */
#endif
