#include "reports/gl_render.hpp"
#include <cerrno>
#include <cstring>

#define GL_GLEXT_PROTOTYPES
#include <GL/osmesa.h>
#include <GL/gl.h>

#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <mutex>
#include <numbers>
#include <stdexcept>

namespace liftcheck::render {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kSuper = 2;  // supersampling factor per axis

void color(const Color& c, float shade = 1.0f) { glColor4f(c.r * shade, c.g * shade, c.b * shade, c.a); }

float shade_of(const Vec3& n) {
  const Vec3 L = Vec3(0.3, -0.5, 0.8).normalized();
  return static_cast<float>(0.55 + 0.45 * std::max(0.0, n.normalized().dot(L)));
}

void vertex(const Vec3& p) { glVertex3d(p.x(), p.y(), p.z()); }

void quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Color& col) {
  color(col, shade_of((b - a).cross(d - a)));
  glBegin(GL_QUADS);
  vertex(a), vertex(b), vertex(c), vertex(d);
  glEnd();
}

void draw_box(const Box& b) {
  const Vec3 f(std::cos(b.heading_rad), std::sin(b.heading_rad), 0), s(-f.y(), f.x(), 0), up(0, 0, 1);
  const Vec3 c(b.centre.x(), b.centre.y(), b.z0_m);
  const Vec3 hf = 0.5 * b.length_m * f, hs = 0.5 * b.width_m * s, h = b.height_m * up;
  const Vec3 p000 = c - hf - hs, p100 = c + hf - hs, p110 = c + hf + hs, p010 = c - hf + hs;
  quad(p000 + h, p100 + h, p110 + h, p010 + h, b.color);  // top
  quad(p000, p010, p110, p100, b.color);                  // bottom
  quad(p000, p100, p100 + h, p000 + h, b.color);
  quad(p100, p110, p110 + h, p100 + h, b.color);
  quad(p110, p010, p010 + h, p110 + h, b.color);
  quad(p010, p000, p000 + h, p010 + h, b.color);
}

void draw_wheel(const Wheel& w) {
  const Vec3 f(std::cos(w.heading_rad), std::sin(w.heading_rad), 0), a(-f.y(), f.x(), 0), up(0, 0, 1);
  const Vec3 C(w.centre.x(), w.centre.y(), w.radius_m);
  constexpr int kSeg = 24;
  // World angle of material angle m: rolling forward by alpha turns the rim backwards over the top.
  const auto rim = [&](double world_angle, double side) {
    return Vec3(C + w.radius_m * (std::cos(world_angle) * f + std::sin(world_angle) * up) + side * 0.5 * w.width_m * a);
  };
  for (int k = 0; k < kSeg; ++k) {
    const double m0 = 2 * kPi * k / kSeg, m1 = 2 * kPi * (k + 1) / kSeg;
    const double t0 = m0 - w.spin_rad, t1 = m1 - w.spin_rad;
    Color c = w.tyre;
    if (k % 2) c = {c.r * 0.55f + 0.45f, c.g * 0.55f + 0.45f, c.b * 0.55f + 0.45f, c.a};  // lighter stripes
    quad(rim(t0, -1), rim(t1, -1), rim(t1, 1), rim(t0, 1), c);
  }
  for (double side : {-1.0, 1.0}) {  // side discs with six spokes
    const Vec3 centre = C + side * 0.5 * w.width_m * a;
    Color face{0.85f, 0.85f, 0.85f, 1.0f};
    color(face, shade_of(side * a));
    glBegin(GL_TRIANGLE_FAN);
    vertex(centre + side * 1e-3 * a);
    for (int k = 0; k <= kSeg; ++k) vertex(rim(2 * kPi * k / kSeg, side) + side * 1e-3 * a);
    glEnd();
    color(w.spokes);
    glBegin(GL_LINES);
    for (int k = 0; k < 6; ++k) {
      vertex(centre + side * 2e-3 * a);
      vertex(rim(2 * kPi * k / 6 - w.spin_rad, side) + side * 2e-3 * a);
    }
    glEnd();
  }
}

void draw_puck(const Puck& p) {
  constexpr int kSeg = 48;
  for (int k = 0; k < kSeg; ++k) {
    const double a0 = 2 * kPi * k / kSeg, a1 = 2 * kPi * (k + 1) / kSeg;
    const Vec3 b0(p.centre.x() + p.radius_m * std::cos(a0), p.centre.y() + p.radius_m * std::sin(a0), 0);
    const Vec3 b1(p.centre.x() + p.radius_m * std::cos(a1), p.centre.y() + p.radius_m * std::sin(a1), 0);
    const Vec3 h(0, 0, p.height_m);
    quad(b0, b1, b1 + h, b0 + h, p.color);
  }
  color(p.color, shade_of(Vec3(0, 0, 1)));
  glBegin(GL_TRIANGLE_FAN);
  glVertex3d(p.centre.x(), p.centre.y(), p.height_m);
  for (int k = 0; k <= kSeg; ++k)
    glVertex3d(p.centre.x() + p.radius_m * std::cos(2 * kPi * k / kSeg),
               p.centre.y() + p.radius_m * std::sin(2 * kPi * k / kSeg), p.height_m);
  glEnd();
}

void line_style(float width_px, bool dashed) {
  glLineWidth(width_px * kSuper);
  if (dashed) {
    glEnable(GL_LINE_STIPPLE);
    glLineStipple(4 * kSuper, 0x00FF);
  } else {
    glDisable(GL_LINE_STIPPLE);
  }
}

void draw_circle(const Circle& c, double z) {
  constexpr int kSeg = 96;
  if (c.fill.a > 0) {
    color(c.fill);
    glBegin(GL_TRIANGLE_FAN);
    glVertex3d(c.centre.x(), c.centre.y(), z);
    for (int k = 0; k <= kSeg; ++k)
      glVertex3d(c.centre.x() + c.radius_m * std::cos(2 * kPi * k / kSeg),
                 c.centre.y() + c.radius_m * std::sin(2 * kPi * k / kSeg), z);
    glEnd();
  }
  if (c.edge.a > 0) {
    line_style(c.width_px, c.dashed);
    color(c.edge);
    glBegin(GL_LINE_LOOP);
    for (int k = 0; k < kSeg; ++k)
      glVertex3d(c.centre.x() + c.radius_m * std::cos(2 * kPi * k / kSeg),
                 c.centre.y() + c.radius_m * std::sin(2 * kPi * k / kSeg), z);
    glEnd();
  }
}

Eigen::Matrix4d perspective(double fovy_deg, double aspect, double n, double f) {
  const double t = 1.0 / std::tan(fovy_deg * kPi / 360.0);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (f + n) / (n - f);
  m(2, 3) = 2 * f * n / (n - f);
  m(3, 2) = -1;
  return m;
}

Eigen::Matrix4d look_at(const Vec3& eye, const Vec3& target) {
  const Vec3 fwd = (target - eye).normalized();
  Vec3 side = fwd.cross(Vec3(0, 0, 1));
  if (side.norm() < 1e-9) side = Vec3(1, 0, 0);
  side.normalize();
  const Vec3 up = side.cross(fwd);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = side.transpose();
  m.block<1, 3>(1, 0) = up.transpose();
  m.block<1, 3>(2, 0) = -fwd.transpose();
  m(0, 3) = -side.dot(eye);
  m(1, 3) = -up.dot(eye);
  m(2, 3) = fwd.dot(eye);
  return m;
}

/// Projection * view for the scene's camera (column-major for glLoadMatrixd).
Eigen::Matrix4d view_projection(const Scene& s) {
  const double aspect = static_cast<double>(s.width_px) / s.height_px;
  if (s.camera.kind == Camera::Kind::kTopDown) {
    const double hh = s.camera.half_height_m, hw = hh * aspect;
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m(0, 0) = 1.0 / hw;
    m(1, 1) = 1.0 / hh;
    m(2, 2) = -1.0 / 100.0;
    m(0, 3) = -s.camera.centre.x() / hw;
    m(1, 3) = -s.camera.centre.y() / hh;
    return m;
  }
  return perspective(s.camera.fov_y_deg, aspect, 0.1, 500.0) * look_at(s.camera.eye, s.camera.target);
}

}  // namespace

// ---- renderer ------------------------------------------------------------------------------

namespace {

/// The ground (a quad in perspective; the clear colour from above) and its grid.
void draw_ground(const Scene& s) {
  const bool top = s.camera.kind == Camera::Kind::kTopDown;
  // Ground and grid.
  const Vec2 c = top ? s.camera.centre : Vec2(s.camera.target.x(), s.camera.target.y());
  const double extent = top ? s.camera.half_height_m * s.width_px / s.height_px * 1.05 : 60.0;
  if (!top) {
    color(colors::kGround);
    glBegin(GL_QUADS);
    glVertex3d(c.x() - extent, c.y() - extent, 0), glVertex3d(c.x() + extent, c.y() - extent, 0);
    glVertex3d(c.x() + extent, c.y() + extent, 0), glVertex3d(c.x() - extent, c.y() + extent, 0);
    glEnd();
  }
  if (s.grid_step_m > 0) {
    const double g = s.grid_step_m;
    glDisable(GL_LINE_STIPPLE);
    for (int major = 0; major < 2; ++major) {
      glLineWidth(major ? 1.5f * kSuper : 1.0f * kSuper);
      color(major ? colors::kGridMajor : colors::kGrid);
      glBegin(GL_LINES);
      const long k0 = static_cast<long>(std::floor((std::min(c.x(), c.y()) - extent) / g));
      const long k1 = static_cast<long>(std::ceil((std::max(c.x(), c.y()) + extent) / g));
      for (long k = k0; k <= k1; ++k) {
        if ((k % 5 == 0) != (major == 1)) continue;
        const double v = k * g;
        if (std::abs(v - c.x()) <= extent) glVertex3d(v, c.y() - extent, 0), glVertex3d(v, c.y() + extent, 0);
        if (std::abs(v - c.y()) <= extent) glVertex3d(c.x() - extent, v, 0), glVertex3d(c.x() + extent, v, 0);
      }
      glEnd();
    }
  }
}

/// Paths and circles flat on the ground, then the solid bodies.
void draw_overlays_and_bodies(const Scene& s) {
  // Flat overlays on the ground.
  for (const auto& ci : s.circles) draw_circle(ci, 0.002);
  for (const auto& l : s.lines) {
    line_style(l.width_px, l.dashed);
    color(l.color);
    glBegin(GL_LINE_STRIP);
    for (const auto& p : l.points) glVertex3d(p.x(), p.y(), 0.004);
    glEnd();
  }
  glDisable(GL_LINE_STIPPLE);
  // Solid bodies.
  glEnable(GL_DEPTH_TEST);
  glClear(GL_DEPTH_BUFFER_BIT);
  glLineWidth(1.5f * kSuper);
  for (const auto& b : s.boxes) draw_box(b);
  for (const auto& w : s.wheels) draw_wheel(w);
  for (const auto& p : s.pucks) draw_puck(p);
  glDisable(GL_DEPTH_TEST);
}

/// Arrows and markers on top of everything.
void draw_arrows_and_markers(const Scene& s) {
  // Arrows and markers on top.
  for (const auto& a : s.arrows) {
    line_style(a.width_px, false);
    color(a.color);
    const Vec2 d = a.to - a.from;
    const double L = d.norm();
    glBegin(GL_LINES);
    glVertex3d(a.from.x(), a.from.y(), 1.0), glVertex3d(a.to.x(), a.to.y(), 1.0);
    glEnd();
    if (L > 0) {
      const Vec2 u = d / L, n(-u.y(), u.x());
      const double head = std::min(0.3 * L, s.camera.half_height_m * 0.04);
      glBegin(GL_TRIANGLES);
      glVertex3d(a.to.x(), a.to.y(), 1.0);
      const Vec2 b1 = a.to - head * u + 0.45 * head * n, b2 = a.to - head * u - 0.45 * head * n;
      glVertex3d(b1.x(), b1.y(), 1.0), glVertex3d(b2.x(), b2.y(), 1.0);
      glEnd();
    }
  }
  for (const auto& m : s.markers) {
    line_style(3.0f, false);
    color(m.color);
    glBegin(GL_LINES);
    glVertex3d(m.at.x() - m.size_m, m.at.y() - m.size_m, 1.0),
        glVertex3d(m.at.x() + m.size_m, m.at.y() + m.size_m, 1.0);
    glVertex3d(m.at.x() - m.size_m, m.at.y() + m.size_m, 1.0),
        glVertex3d(m.at.x() + m.size_m, m.at.y() - m.size_m, 1.0);
    glEnd();
  }
}

/// The supersampled buffer (W x H) averaged down to the scene's size, opaque.
Image downsample(const std::vector<std::uint8_t>& buffer, int W, const Scene& s) {
  // Downsample kSuper x kSuper.
  Image img;
  img.width = s.width_px;
  img.height = s.height_px;
  img.rgba.resize(static_cast<std::size_t>(img.width) * img.height * 4);
  const std::size_t row_bytes = static_cast<std::size_t>(W) * 4, out_row = static_cast<std::size_t>(img.width) * 4;
  std::vector<int> sums(out_row);
  for (int y = 0; y < img.height; ++y) {
    // Sum each output pixel's kSuper x kSuper block row by row (one pass over each input row).
    std::fill(sums.begin(), sums.end(), 0);
    for (int j = 0; j < kSuper; ++j) {
      const std::uint8_t* in = buffer.data() + static_cast<std::size_t>(y * kSuper + j) * row_bytes;
      for (std::size_t x = 0; x < out_row; x += 4)
        for (int i = 0; i < kSuper; ++i)
          for (int ch = 0; ch < 4; ++ch) sums[x + ch] += in[(x / 4 * kSuper + i) * 4 + ch];
    }
    std::uint8_t* out = img.rgba.data() + static_cast<std::size_t>(y) * out_row;
    for (std::size_t k = 0; k < out_row; ++k) out[k] = static_cast<std::uint8_t>(sums[k] / (kSuper * kSuper));
  }
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = 255;
  return img;
}

/// Scale bar (top-down): a round length about a fifth of the width, bottom left.
void draw_scale_bar(Image& img, const Scene& s) {
  const double ppm = img.height / (2.0 * s.camera.half_height_m);
  const double target = img.width / 5.0 / ppm;
  const double p10 = std::pow(10.0, std::floor(std::log10(target)));
  double L = p10;
  for (double m : {2.0, 5.0, 10.0})
    if (m * p10 <= target) L = m * p10;
  const int len = static_cast<int>(std::lround(L * ppm)), x0 = 20, y0 = img.height - 24;
  for (int y = y0; y < y0 + 6; ++y)
    for (int x = x0; x < x0 + len && x < img.width; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      const bool light = ((x - x0) * 2 / std::max(1, len)) % 2 == 1 && y > y0 && y < y0 + 5;
      p[0] = p[1] = p[2] = light ? 255 : 20;
    }
  const std::string text = L >= 1      ? fmt::format("{:g} m", L)
                           : L >= 0.01 ? fmt::format("{:g} cm", L * 100)
                           : L >= 1e-3 ? fmt::format("{:g} mm", L * 1e3)
                                       : fmt::format("{:g} µm", L * 1e6);
  draw_text(img, text, x0 + len + 8, y0 - 7, 15.0f, Color{0.1f, 0.1f, 0.1f, 1.0f});
}

/// The scene's labels, in pixels or at ground points.
void draw_labels(Image& img, const Scene& s, const Eigen::Matrix4d& vp) {
  for (const auto& l : s.labels) {
    int x = static_cast<int>(l.at.x()), y = static_cast<int>(l.at.y());
    if (!l.screen) {
      const Eigen::Vector4d p = vp * Eigen::Vector4d(l.at.x(), l.at.y(), 0.0, 1.0);
      if (p.w() <= 0) continue;
      x = static_cast<int>((p.x() / p.w() * 0.5 + 0.5) * img.width);
      y = static_cast<int>((0.5 - p.y() / p.w() * 0.5) * img.height);
    }
    draw_text(img, l.text, x, y, l.size_px, l.color);
  }
}

}  // namespace

struct Renderer::Impl {
  OSMesaContext ctx = nullptr;
  std::vector<std::uint8_t> buffer;
  /// The buffer and size the context was last made current with: OSMesaMakeCurrent reallocates
  /// and clears Mesa's depth buffer each call (10% of a report's CPU when called every picture).
  const std::uint8_t* bound = nullptr;
  int bound_w = 0, bound_h = 0;
  ~Impl() {
    if (!ctx) return;
    // Release the context before destroying it, so that the thread is not left with a destroyed
    // context current (OSMesaDestroyContext does not unbind it). What valgrind still reports lost
    // after this (16 bytes once per process, about 160 per context made current) is Mesa 22.3's own:
    // OSMesa keeps its framebuffers in a list no API frees (tests/sanitize/lsan.supp).
    if (OSMesaGetCurrentContext() == ctx) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    OSMesaDestroyContext(ctx);
  }
};

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;

std::string Renderer::gl_version() {
  if (!impl_->ctx) return "";
  const auto* v = glGetString(GL_VERSION);
  return v ? reinterpret_cast<const char*>(v) : "";
}

Image Renderer::render(const Scene& s) {
  if (!impl_->ctx) {
    impl_->ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
    if (!impl_->ctx) throw std::runtime_error("OSMesa: cannot create a GL context");
  }
  const int W = s.width_px * kSuper, H = s.height_px * kSuper;
  // glClear below sets every pixel: the buffer only grows (no fill of 7.7 MB per picture).
  if (impl_->buffer.size() < static_cast<std::size_t>(W) * H * 4)
    impl_->buffer.resize(static_cast<std::size_t>(W) * H * 4);
  if (OSMesaGetCurrentContext() != impl_->ctx || impl_->bound != impl_->buffer.data() || impl_->bound_w != W ||
      impl_->bound_h != H) {
    impl_->bound = nullptr;
    if (!OSMesaMakeCurrent(impl_->ctx, impl_->buffer.data(), GL_UNSIGNED_BYTE, W, H))
      throw std::runtime_error("OSMesa: cannot make the context current");
    OSMesaPixelStore(OSMESA_Y_UP, 0);  // rows from the top
    impl_->bound = impl_->buffer.data(), impl_->bound_w = W, impl_->bound_h = H;
  }

  const bool top = s.camera.kind == Camera::Kind::kTopDown;
  glViewport(0, 0, W, H);
  if (top)
    glClearColor(colors::kGround.r, colors::kGround.g, colors::kGround.b, 1);
  else
    glClearColor(0.86f, 0.90f, 0.95f, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glMatrixMode(GL_PROJECTION);
  const Eigen::Matrix4d vp = view_projection(s);
  glLoadMatrixd(vp.data());
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);

  draw_ground(s);
  draw_overlays_and_bodies(s);
  draw_arrows_and_markers(s);
  glFinish();

  Image img = downsample(impl_->buffer, W, s);
  if (top && s.scale_bar) draw_scale_bar(img, s);
  draw_labels(img, s, vp);
  return img;
}

}  // namespace liftcheck::render
