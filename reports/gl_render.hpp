// Off-screen rendering of a Scene with OSMesa (llvmpipe, software): 2x supersampled, then text
// composited at the final resolution; PNG encoding with libpng.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "reports/scene.hpp"

namespace liftcheck::render {

/// An RGBA8 image, rows from the top.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;
  std::uint8_t* pixel(int x, int y) { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
  const std::uint8_t* pixel(int x, int y) const { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
};

/// Owns one OSMesa context (created on first use, destroyed with the renderer). Not thread-safe:
/// one renderer per thread.
class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Draws the scene; throws std::runtime_error if no GL context can be made.
  Image render(const Scene& scene);
  /// "4.5 (Compatibility Profile) Mesa ..." once a context exists.
  std::string gl_version();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes the image as a PNG of at most 64 colours (libimagequant's palette, a quarter of the
/// RGBA file). Throws std::runtime_error naming the path.
void write_png(const std::filesystem::path& path, const Image& image);

/// Pastes images side by side in rows of `per_row`, on white.
Image tile(const std::vector<Image>& frames, int per_row);

/// Pastes `inset` onto `image` with its top-left corner at (x, y), framed by a dark border.
void paste(Image& image, const Image& inset, int x, int y);

/// Draws UTF-8 text onto the image with DejaVu Sans (top-left of the text at x, y).
void draw_text(Image& image, const std::string& text, int x, int y, float size_px, const Color& color);
/// Width in pixels of the text at this size.
int text_width(const std::string& text, float size_px);

}  // namespace liftcheck::render
