/* A raster canvas: shapes by coverage (the distance of each pixel centre from
 * the shape's edge, a one-pixel ramp), text through stb_truetype with the
 * embedded DejaVu Sans. See draw.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stb_truetype.h>

#include "core/core.h"
#include "io/draw.h"

/* The font file, embedded by the assembler (JND_FONT_FILE is set by CMake to
 * Debian's fonts-dejavu-core DejaVuSans.ttf). */
__asm__(".pushsection .rodata\n"
        ".balign 16\n"
        ".globl jnd_font_ttf\n"
        ".hidden jnd_font_ttf\n"
        "jnd_font_ttf:\n"
        ".incbin \"" JND_FONT_FILE "\"\n"
        ".byte 0\n"
        ".popsection\n");
extern const unsigned char jnd_font_ttf[] __attribute__((visibility("hidden")));

jnd_rgb jnd_palette(int i) {
  /* Okabe & Ito (2008), "Color universal design" */
  static const jnd_rgb p[8] = {{0.000f, 0.447f, 0.698f}, {0.835f, 0.369f, 0.000f}, {0.000f, 0.620f, 0.451f},
                               {0.800f, 0.475f, 0.655f}, {0.337f, 0.706f, 0.914f}, {0.902f, 0.624f, 0.000f},
                               {0.941f, 0.894f, 0.259f}, {0.000f, 0.000f, 0.000f}};
  return p[((i % 8) + 8) % 8];
}

jnd_rgb jnd_ramp5(const float s[5][3], double t) {
  if (!(t >= 0)) t = 0;
  if (t > 1) t = 1;
  double u = t * 4;
  int i = (int)u;
  if (i >= 4) return (jnd_rgb){s[4][0], s[4][1], s[4][2]};
  float f = (float)(u - i);
  return (jnd_rgb){s[i][0] + f * (s[i + 1][0] - s[i][0]), s[i][1] + f * (s[i + 1][1] - s[i][1]),
                   s[i][2] + f * (s[i + 1][2] - s[i][2])};
}

jnd_rgb jnd_colour_scale(double t) {
  /* five stops rising in lightness: navy, blue, teal, green, yellow */
  static const float s[5][3] = {{0.10f, 0.06f, 0.33f}, {0.16f, 0.32f, 0.62f}, {0.12f, 0.58f, 0.58f},
                                {0.45f, 0.78f, 0.33f}, {0.99f, 0.91f, 0.15f}};
  return jnd_ramp5(s, t);
}

jnd_status jnd_canvas_new(jnd_image *img, int w, int h, jnd_rgb bg) {
  jnd_status s = jnd_image_alloc(img, w, h, 3);
  if (s != JND_OK) return s;
  size_t n = (size_t)w * h;
  float v[3] = {bg.r, bg.g, bg.b};
  for (int c = 0; c < 3; c++) {
    float *p = jnd_image_plane(img, c);
    for (size_t i = 0; i < n; i++) p[i] = v[c];
  }
  return JND_OK;
}

static void blend(jnd_image *img, int x, int y, jnd_rgb c, double a) {
  if (x < 0 || y < 0 || x >= img->w || y >= img->h || !(a > 0)) return;
  if (a > 1) a = 1;
  size_t i = (size_t)y * img->w + x;
  float fa = (float)a, v[3] = {c.r, c.g, c.b};
  for (int k = 0; k < 3; k++) {
    float *p = jnd_image_plane(img, k) + i;
    *p = *p * (1 - fa) + v[k] * fa;
  }
}

void jnd_draw_rect(jnd_image *img, double x0, double y0, double x1, double y1, jnd_rgb c, double alpha) {
  int xa = (int)floor(fmax(x0, 0)), xb = (int)ceil(fmin(x1, img->w)), ya = (int)floor(fmax(y0, 0)),
      yb = (int)ceil(fmin(y1, img->h));
  for (int y = ya; y < yb; y++)
    for (int x = xa; x < xb; x++) {
      /* partial coverage of edge pixels */
      double cx = fmin(x + 1, x1) - fmax(x, x0), cy = fmin(y + 1, y1) - fmax(y, y0);
      if (cx > 0 && cy > 0) blend(img, x, y, c, alpha * fmin(cx, 1) * fmin(cy, 1));
    }
}

void jnd_draw_frame(jnd_image *img, double x0, double y0, double x1, double y1, double width, jnd_rgb c) {
  jnd_draw_rect(img, x0, y0, x1, y0 + width, c, 1);
  jnd_draw_rect(img, x0, y1 - width, x1, y1, c, 1);
  jnd_draw_rect(img, x0, y0 + width, x0 + width, y1 - width, c, 1);
  jnd_draw_rect(img, x1 - width, y0 + width, x1, y1 - width, c, 1);
}

void jnd_draw_line(jnd_image *img, double x0, double y0, double x1, double y1, double width, jnd_rgb c) {
  if (!(isfinite(x0) && isfinite(y0) && isfinite(x1) && isfinite(y1))) return;
  double h = 0.5 * width, dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
  int xa = (int)floor(fmin(x0, x1) - h - 1), xb = (int)ceil(fmax(x0, x1) + h + 1);
  int ya = (int)floor(fmin(y0, y1) - h - 1), yb = (int)ceil(fmax(y0, y1) + h + 1);
  if (xa < 0) xa = 0;
  if (ya < 0) ya = 0;
  if (xb > img->w) xb = img->w;
  if (yb > img->h) yb = img->h;
  for (int y = ya; y < yb; y++)
    for (int x = xa; x < xb; x++) {
      double px = x + 0.5 - x0, py = y + 0.5 - y0;
      double t = len2 > 0 ? (px * dx + py * dy) / len2 : 0;
      t = t < 0 ? 0 : t > 1 ? 1 : t;
      double ex = px - t * dx, ey = py - t * dy, d = sqrt(ex * ex + ey * ey);
      blend(img, x, y, c, h + 0.5 - d);
    }
}

void jnd_draw_circle(jnd_image *img, double cx, double cy, double r, int filled, jnd_rgb c) {
  int xa = (int)floor(cx - r - 1), xb = (int)ceil(cx + r + 1), ya = (int)floor(cy - r - 1), yb = (int)ceil(cy + r + 1);
  for (int y = ya < 0 ? 0 : ya; y < yb && y < img->h; y++)
    for (int x = xa < 0 ? 0 : xa; x < xb && x < img->w; x++) {
      double d = hypot(x + 0.5 - cx, y + 0.5 - cy);
      double a = filled ? r + 0.5 - d : 1.0 - fabs(d - r) * 0.75;
      blend(img, x, y, c, a);
    }
}

/* ---- text ---- */

/* the next code point of UTF-8 text; malformed bytes give '?' */
static int next_codepoint(const unsigned char **s) {
  const unsigned char *p = *s;
  int cp, n;
  if (p[0] < 0x80) {
    cp = p[0];
    n = 1;
  } else if ((p[0] & 0xE0) == 0xC0 && (p[1] & 0xC0) == 0x80) {
    cp = ((p[0] & 0x1F) << 6) | (p[1] & 0x3F);
    n = 2;
  } else if ((p[0] & 0xF0) == 0xE0 && (p[1] & 0xC0) == 0x80 && (p[2] & 0xC0) == 0x80) {
    cp = ((p[0] & 0x0F) << 12) | ((p[1] & 0x3F) << 6) | (p[2] & 0x3F);
    n = 3;
  } else if ((p[0] & 0xF8) == 0xF0 && (p[1] & 0xC0) == 0x80 && (p[2] & 0xC0) == 0x80 && (p[3] & 0xC0) == 0x80) {
    cp = ((p[0] & 0x07) << 18) | ((p[1] & 0x3F) << 12) | ((p[2] & 0x3F) << 6) | (p[3] & 0x3F);
    n = 4;
  } else {
    cp = '?';
    n = 1;
  }
  *s = p + n;
  return cp;
}

static int font_open(stbtt_fontinfo *f) {
  return stbtt_InitFont(f, jnd_font_ttf, stbtt_GetFontOffsetForIndex(jnd_font_ttf, 0));
}

static int glyph_of(const stbtt_fontinfo *f, int cp) {
  int g = stbtt_FindGlyphIndex(f, cp);
  return g ? g : stbtt_FindGlyphIndex(f, '?');
}

double jnd_text_width(const char *text, double size_px) {
  stbtt_fontinfo f;
  if (!text || !font_open(&f)) return 0;
  float scale = stbtt_ScaleForMappingEmToPixels(&f, (float)size_px);
  const unsigned char *s = (const unsigned char *)text;
  double w = 0;
  int prev = 0;
  while (*s) {
    int g = glyph_of(&f, next_codepoint(&s)), adv, lsb;
    if (prev) w += scale * stbtt_GetGlyphKernAdvance(&f, prev, g);
    stbtt_GetGlyphHMetrics(&f, g, &adv, &lsb);
    w += scale * adv;
    prev = g;
  }
  return w;
}

jnd_box jnd_text_box(double x, double y, const char *text, double size_px, jnd_align align, int vertical) {
  stbtt_fontinfo f;
  jnd_box b = {x, y, x, y};
  if (!text || !*text || !font_open(&f)) return b;
  float scale = stbtt_ScaleForMappingEmToPixels(&f, (float)size_px);
  int asc, desc, gap;
  stbtt_GetFontVMetrics(&f, &asc, &desc, &gap);
  double w = jnd_text_width(text, size_px), off = align == JND_ALIGN_CENTRE ? -0.5 * w : align == JND_ALIGN_RIGHT ? -w : 0;
  /* as jnd_draw_text places its mask: the pen starts one pixel in, the
   * anchor rounded, glyphs may reach a pixel past their advance */
  double a = ceil(scale * asc) + 1, d = ceil(-scale * desc) + 1, s0 = lround(off) - 1, s1 = lround(off) + ceil(w) + 3;
  if (vertical) {
    b.x0 = lround(x) - a;
    b.x1 = lround(x) + d;
    b.y0 = lround(y) - s1 + 1;
    b.y1 = lround(y) - s0 + 1;
  } else {
    b.x0 = lround(x) + s0;
    b.x1 = lround(x) + s1;
    b.y0 = lround(y) - a;
    b.y1 = lround(y) + d;
  }
  return b;
}

void jnd_draw_text(jnd_image *img, double x, double y, const char *text, double size_px, jnd_rgb c, jnd_align align,
                   int vertical) {
  stbtt_fontinfo f;
  if (!text || !*text || !font_open(&f)) return;
  float scale = stbtt_ScaleForMappingEmToPixels(&f, (float)size_px);
  int asc, desc, gap;
  stbtt_GetFontVMetrics(&f, &asc, &desc, &gap);
  double width = jnd_text_width(text, size_px);
  int top = (int)ceil(scale * asc) + 1, bottom = (int)ceil(-scale * desc) + 1;
  int mw = (int)ceil(width) + 4, mh = top + bottom;
  /* the string as a coverage mask, baseline at row `top`, then placed */
  unsigned char *mask = calloc((size_t)mw * mh, 1);
  if (!mask) return;
  const unsigned char *s = (const unsigned char *)text;
  double pen = 1;
  int prev = 0;
  while (*s) {
    int g = glyph_of(&f, next_codepoint(&s)), adv, lsb, x0, y0, x1, y1;
    if (prev) pen += scale * stbtt_GetGlyphKernAdvance(&f, prev, g);
    stbtt_GetGlyphHMetrics(&f, g, &adv, &lsb);
    float shift = (float)(pen - floor(pen));
    stbtt_GetGlyphBitmapBoxSubpixel(&f, g, scale, scale, shift, 0, &x0, &y0, &x1, &y1);
    int gw = x1 - x0, gh = y1 - y0, ox = (int)floor(pen) + x0, oy = top + y0;
    if (gw > 0 && gh > 0 && ox >= 0 && oy >= 0 && ox + gw <= mw && oy + gh <= mh)
      stbtt_MakeGlyphBitmapSubpixel(&f, mask + (size_t)oy * mw + ox, gw, gh, mw, scale, scale, shift, 0, g);
    pen += scale * adv;
    prev = g;
  }
  double off = align == JND_ALIGN_CENTRE ? -0.5 * width : align == JND_ALIGN_RIGHT ? -width : 0;
  int bx = (int)lround(x), by = (int)lround(y), o = (int)lround(off) - 1;
  for (int r = 0; r < mh; r++)
    for (int q = 0; q < mw; q++) {
      unsigned char m = mask[(size_t)r * mw + q];
      if (!m) continue;
      /* horizontal: (q + o, r − top) from the anchor; vertical: turned 90°
       * counter-clockwise, the text running up from the anchor */
      int px = vertical ? bx + (r - top) : bx + q + o, py = vertical ? by - (q + o) : by + (r - top);
      blend(img, px, py, c, m / 255.0);
    }
  free(mask);
}

void jnd_draw_image(jnd_image *img, int x, int y, const jnd_image *src, int scale) {
  if (scale < 1) scale = 1;
  for (int sy = 0; sy < src->h; sy++)
    for (int sx = 0; sx < src->w; sx++) {
      size_t i = (size_t)sy * src->w + sx;
      float v[3];
      for (int k = 0; k < 3; k++) v[k] = jnd_image_plane(src, src->c >= 3 ? k : 0)[i];
      for (int dy = 0; dy < scale; dy++)
        for (int dx = 0; dx < scale; dx++) {
          int px = x + sx * scale + dx, py = y + sy * scale + dy;
          if (px < 0 || py < 0 || px >= img->w || py >= img->h) continue;
          for (int k = 0; k < 3; k++) jnd_image_plane(img, k)[(size_t)py * img->w + px] = v[k];
        }
    }
}
