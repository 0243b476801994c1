/* stb_image compiled into the image fuzz targets, so that libFuzzer sees
 * coverage inside the decoder and ASan checks its memory accesses (the
 * system libstb is not instrumented). Its symbols take precedence over the
 * shared library's. */
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
