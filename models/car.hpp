// The car of Fecko, "Gauge-potential approach to the kinematics of a moving car":
// P = (alpha, beta, x, y, phi) is a principal E(2)-bundle over the shapes (alpha, beta);
// no-slip contact is the connection (3.3); motion is the horizontal lift (4.1).
//
// (x, y) is the front-axle centre [m], phi the heading of the tie rod [rad], alpha the front
// wheel's rolling angle [rad], beta the steering angle (front axle against the tie rod) [rad].
#pragma once

#include <Eigen/Dense>
#include <array>

#include "models/e2.hpp"

namespace liftcheck::car {

using Vec5 = Eigen::Matrix<double, 5, 1>;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/// Index of each coordinate of P in a Vec5.
enum Coord : int { kAlpha = 0, kBeta = 1, kX = 2, kY = 3, kPhi = 4 };

/// Car geometry (Fecko fig. 1, 2).
struct CarDef {
  double R_m = 0.3;  ///< front wheel radius
  double l_m = 1.0;  ///< tie-rod length, rear-axle centre to front-axle centre
};

/// A point of P.
struct Config {
  double alpha_rad = 0.0;
  double beta_rad = 0.0;
  double x_m = 0.0;
  double y_m = 0.0;
  double phi_rad = 0.0;

  Vec5 vec() const;
  static Config from(const Vec5& v);
  e2::Pose pose() const { return {x_m, y_m, phi_rad}; }
};

/// Rear-axle centre in the world frame: the other end of the tie rod.
Eigen::Vector2d rear_axle_W(const CarDef& car, const Config& q);

/// Horizontal lift H_alpha (4.3) at q, as a vector on P.
Vec5 H_alpha(const CarDef& car, const Config& q);
/// Horizontal lift H_beta = d/dbeta (4.4).
Vec5 H_beta(const CarDef& car, const Config& q);

/// Connection form (3.3): row a holds the coefficients of omega^a on (dalpha, dbeta, dx, dy, dphi).
Eigen::Matrix<double, 3, 5> connection_form(const CarDef& car, const Config& q);

/// Gauge potential in the section sigma (3.4): the e(2) matrix multiplying dalpha.
Mat3 gauge_potential(const CarDef& car, double beta_rad);

/// [H_alpha, H_beta] (5.5).
Vec5 bracket_alpha_beta(const CarDef& car, const Config& q);
/// [H_alpha, [H_alpha, H_beta]] (5.6).
Vec5 bracket_alpha_alpha_beta(const CarDef& car, const Config& q);
/// [H_beta, [H_alpha, H_beta]] (5.7) = H_alpha - d/dalpha.
Vec5 bracket_beta_alpha_beta(const CarDef& car, const Config& q);

/// Curvature (5.12): the coefficients Omega^a(d_alpha, d_beta), a = 0, 1, 2.
Vec3 curvature(const CarDef& car, const Config& q);
/// Field strength (5.13) in the section sigma: the e(2) matrix multiplying dalpha ^ dbeta.
/// Follows the check (pullback of (5.12) at x = y = phi = 0); see models/ERRATA.md.
Mat3 field_strength(const CarDef& car, double beta_rad);

/// Fundamental field xi_a (E.5) of the E(2) action at q.
Vec5 fundamental_field(int a, const Config& q);

/// Particle field psi (6.3): unit vector along the tie rod.
Eigen::Vector2d particle_field(const Config& q);
/// The representation rho (6.7) of E(2) on R^2, evaluated at rotation theta.
Eigen::Matrix2d rho(double theta_rad);
/// Change of psi along H_alpha per unit alpha (6.8).
Eigen::Vector2d particle_field_rate(const CarDef& car, const Config& q);

/// The E(2) action (A.6) on P: shape unchanged, rod moved by g.
Config act(const Mat3& g, const Config& q);

// ---- Exact flows ----------------------------------------------------------------------------

/// Flow of H_alpha by d_alpha at fixed steering: the closed-form arc of appendix D
/// (straight line when beta = 0).
Config flow_alpha(const CarDef& car, const Config& q, double d_alpha_rad);
/// Flow of H_beta by d_beta: steering turns, the rod stays (4.4).
Config flow_beta(const Config& q, double d_beta_rad);

/// Appendix D: circle of the front-axle centre under fixed steering beta0 != 0.
struct Circle {
  double radius_m;
  double cx_m;
  double cy_m;
};
Circle front_circle(const CarDef& car, const Config& q0);
/// Circle of the rear-axle centre: radius l/|tan beta0|, same centre.
Circle rear_circle(const CarDef& car, const Config& q0);

}  // namespace liftcheck::car
