// The report's pixels outside OpenGL: text drawn into an image (DejaVu Sans through
// stb_truetype), colours from hex, insets pasted, frames tiled, and PNG files written (reduced to
// 64 colours by libimagequant). The OpenGL scene renderer: reports/gl_render.cpp.
#include "reports/gl_render.hpp"

#include <libimagequant.h>
#include <png.h>
#include <stb_truetype.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <mutex>
#include <stdexcept>

namespace liftcheck::render {

namespace {

constexpr const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

struct Font {
  Font() {
    std::ifstream in(kFontPath, std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("font not found: {} (Debian package fonts-dejavu-core)", kFontPath));
    data.assign(std::istreambuf_iterator<char>(in), {});
    if (!stbtt_InitFont(&info, data.data(), stbtt_GetFontOffsetForIndex(data.data(), 0)))
      throw std::runtime_error(fmt::format("cannot read font {}", kFontPath));
  }
  std::vector<unsigned char> data;
  stbtt_fontinfo info{};
  std::map<std::pair<int, int>, std::tuple<std::vector<unsigned char>, int, int, int, int, int>>
      cache;  // bitmap, w, h, xoff, yoff, advance
  std::mutex mutex;
};

Font& font() {
  static Font f;
  return f;
}

std::vector<int> decode_utf8(const std::string& s) {
  std::vector<int> cps;
  for (std::size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    int cp = c, extra = 0;
    if (c >= 0xF0)
      cp = c & 0x07, extra = 3;
    else if (c >= 0xE0)
      cp = c & 0x0F, extra = 2;
    else if (c >= 0xC0)
      cp = c & 0x1F, extra = 1;
    for (int k = 1; k <= extra && i + k < s.size(); ++k) cp = (cp << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
    cps.push_back(cp);
    i += 1 + extra;
  }
  return cps;
}

}  // namespace

Color color_from_hex(const std::string& hex) {
  if (hex.size() != 7 || hex[0] != '#') return colors::kUnknown;
  float rgb[3];
  for (int i = 0; i < 3; ++i) {
    const std::string part = hex.substr(1 + 2 * i, 2);
    if (!std::isxdigit(static_cast<unsigned char>(part[0])) || !std::isxdigit(static_cast<unsigned char>(part[1])))
      return colors::kUnknown;
    rgb[i] = static_cast<float>(std::stoi(part, nullptr, 16)) / 255.0f;
  }
  return {rgb[0], rgb[1], rgb[2], 1.0f};
}

int text_width(const std::string& text, float size_px) {
  Font& f = font();
  const float scale = stbtt_ScaleForPixelHeight(&f.info, size_px);
  int w = 0;
  for (int cp : decode_utf8(text)) {
    int adv, lsb;
    stbtt_GetCodepointHMetrics(&f.info, cp, &adv, &lsb);
    w += static_cast<int>(std::lround(adv * scale));
  }
  return w;
}

void draw_text(Image& img, const std::string& text, int x, int y, float size_px, const Color& col) {
  Font& f = font();
  std::lock_guard<std::mutex> lock(f.mutex);
  const float scale = stbtt_ScaleForPixelHeight(&f.info, size_px);
  int ascent, descent, gap;
  stbtt_GetFontVMetrics(&f.info, &ascent, &descent, &gap);
  const int baseline = y + static_cast<int>(std::lround(ascent * scale));
  int pen = x;
  for (int cp : decode_utf8(text)) {
    const auto key = std::make_pair(cp, static_cast<int>(size_px * 4));
    auto it = f.cache.find(key);
    if (it == f.cache.end()) {
      int w, h, xo, yo, adv, lsb;
      unsigned char* bm = stbtt_GetCodepointBitmap(&f.info, 0, scale, cp, &w, &h, &xo, &yo);
      stbtt_GetCodepointHMetrics(&f.info, cp, &adv, &lsb);
      std::vector<unsigned char> copy(bm, bm + static_cast<std::size_t>(w) * h);
      stbtt_FreeBitmap(bm, nullptr);
      it = f.cache
               .emplace(key, std::make_tuple(std::move(copy), w, h, xo, yo, static_cast<int>(std::lround(adv * scale))))
               .first;
    }
    const auto& [bm, w, h, xo, yo, adv] = it->second;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const int px = pen + xo + i, py = baseline + yo + j;
        if (px < 0 || py < 0 || px >= img.width || py >= img.height) continue;
        const float a = bm[static_cast<std::size_t>(j) * w + i] / 255.0f * col.a;
        std::uint8_t* p = img.pixel(px, py);
        p[0] = static_cast<std::uint8_t>(p[0] * (1 - a) + 255 * col.r * a);
        p[1] = static_cast<std::uint8_t>(p[1] * (1 - a) + 255 * col.g * a);
        p[2] = static_cast<std::uint8_t>(p[2] * (1 - a) + 255 * col.b * a);
      }
    pen += adv;
  }
}

void paste(Image& image, const Image& inset, int x, int y) {
  for (int j = -2; j < inset.height + 2; ++j)
    for (int i = -2; i < inset.width + 2; ++i) {
      const int X = x + i, Y = y + j;
      if (X < 0 || Y < 0 || X >= image.width || Y >= image.height) continue;
      std::uint8_t* d = image.pixel(X, Y);
      if (i < 0 || j < 0 || i >= inset.width || j >= inset.height) {
        d[0] = d[1] = d[2] = 40, d[3] = 255;
      } else {
        const std::uint8_t* s = inset.pixel(i, j);
        for (int c = 0; c < 4; ++c) d[c] = s[c];
      }
    }
}

Image tile(const std::vector<Image>& frames, int per_row) {
  Image out;
  if (frames.empty()) return out;
  const int w = frames[0].width, h = frames[0].height, gap = 4;
  const int rows = (static_cast<int>(frames.size()) + per_row - 1) / per_row;
  const int cols = std::min<int>(per_row, static_cast<int>(frames.size()));
  out.width = cols * w + (cols - 1) * gap;
  out.height = rows * h + (rows - 1) * gap;
  out.rgba.assign(static_cast<std::size_t>(out.width) * out.height * 4, 255);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const int ox = static_cast<int>(k % per_row) * (w + gap), oy = static_cast<int>(k / per_row) * (h + gap);
    for (int y = 0; y < h; ++y) std::copy_n(frames[k].pixel(0, y), w * 4, out.pixel(ox, oy + y));
  }
  return out;
}

namespace {

/// The image reduced to at most 64 colours by libimagequant (no dithering: the scenes are flat
/// colours with antialiased edges), as palette indices and the palette.
struct Indexed {
  std::vector<std::uint8_t> index;
  std::vector<png_color> rgb;
  std::vector<png_byte> alpha;
};

Indexed quantize(const Image& image) {
  liq_attr* attr = liq_attr_create();
  if (!attr) throw std::bad_alloc();
  liq_set_speed(attr, 8);
  liq_set_max_colors(attr, 64);  // a scene has a few inks and their edges: 12% smaller than 256
  liq_image* img = liq_image_create_rgba(attr, image.rgba.data(), image.width, image.height, 0);
  liq_result* res = nullptr;
  const bool ok = img && liq_image_quantize(img, attr, &res) == LIQ_OK;
  Indexed out;
  if (ok) {
    liq_set_dithering_level(res, 0.0f);
    out.index.resize(static_cast<std::size_t>(image.width) * image.height);
    if (liq_write_remapped_image(res, img, out.index.data(), out.index.size()) == LIQ_OK) {
      const liq_palette* pal = liq_get_palette(res);
      for (unsigned i = 0; i < pal->count; ++i) {
        out.rgb.push_back({pal->entries[i].r, pal->entries[i].g, pal->entries[i].b});
        out.alpha.push_back(pal->entries[i].a);
      }
    }
    liq_result_destroy(res);
  }
  if (img) liq_image_destroy(img);
  liq_attr_destroy(attr);
  if (out.rgb.empty()) throw std::runtime_error("cannot reduce the image to 64 colours");
  while (!out.alpha.empty() && out.alpha.back() == 255) out.alpha.pop_back();  // tRNS lists the translucent only
  return out;
}

}  // namespace

void write_png(const std::filesystem::path& path, const Image& image) {
  const Indexed q = quantize(image);
  const std::string tmp = path.string() + ".tmp";
  FILE* fp = std::fopen(tmp.c_str(), "wb");
  if (!fp) throw std::runtime_error(fmt::format("cannot write '{}': {}", path.string(), std::strerror(errno)));
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(fp);
    std::remove(tmp.c_str());
    throw std::runtime_error(fmt::format("cannot encode '{}'", path.string()));
  }
  png_init_io(png, fp);
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_PLTE(png, info, q.rgb.data(), static_cast<int>(q.rgb.size()));
  if (!q.alpha.empty()) png_set_tRNS(png, info, q.alpha.data(), static_cast<int>(q.alpha.size()), nullptr);
  png_set_compression_level(png, 8);  // 8: within 2% of 9 at half its time
  png_set_compression_mem_level(png, 9);
  png_set_filter(png, 0, PNG_FILTER_NONE);  // palette indices: filters do not help
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y) png_write_row(png, q.index.data() + static_cast<std::size_t>(y) * image.width);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fclose(fp) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw std::runtime_error(fmt::format("cannot write '{}': {}", path.string(), std::strerror(err)));
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error(fmt::format("cannot write '{}': {}", path.string(), ec.message()));
}

}  // namespace liftcheck::render
