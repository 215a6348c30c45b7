// E(2) and its Lie algebra e(2) in the row-vector convention of Fecko, appendices A and B.
//
// A group element (B, b) is the 3x3 matrix  [[B, 0], [b, 1]]  (A.2) acting on row vectors
// eta = (x1, x2, 1) from the right: eta * M = (chi B + b, 1)  (A.3).
// B(theta) = [[cos, sin], [-sin, cos]] rotates a row vector by +theta (A.1), (A.4).
#pragma once

#include <Eigen/Dense>

namespace liftcheck::e2 {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

/// Position of the tie rod in the plane: front-axle centre (x, y) [m], heading phi [rad].
struct Pose {
  double x_m = 0.0;
  double y_m = 0.0;
  double phi_rad = 0.0;
};

/// Basis e_0 (rotation), e_1, e_2 (translations) of e(2), appendix B.
Mat3 basis(int a);

/// lambda^a e_a for coefficients (lambda_0, lambda_1, lambda_2).
Mat3 hat(const Vec3& lambda);

/// Coefficients lambda^a of an e(2) matrix (inverse of hat).
Vec3 vee(const Mat3& m);

/// Matrix commutator [A, B] = AB - BA.
Mat3 bracket(const Mat3& a, const Mat3& b);

/// Structure constants c^a_{bc} with [e_b, e_c] = c^a_{bc} e_a, (B.2).
double structure_constant(int a, int b, int c);

/// Closed-form exponential of an e(2) element (rotation by lambda_0 with the matching translation).
Mat3 exp(const Vec3& lambda);

/// The group element (B(theta), b) of (A.2).
Mat3 element(double theta_rad, double b1_m, double b2_m);

/// The element that carries the reference rod (0,0,0) to `pose` (A.5), equal to (C.2).
Mat3 element_of(const Pose& pose);

/// Inverse of element_of: reads (x, y, phi) off a group matrix.
Pose pose_of(const Mat3& m);

/// The action (A.4) of the group element `g` on a rod position.
Pose act(const Mat3& g, const Pose& pose);

/// Wraps an angle to (-pi, pi].
double wrap_angle(double a_rad);

}  // namespace liftcheck::e2
