// Simbody 3.7 (compiled as C++17: see simbody_sim.hpp). One MultibodySystem per car or disk pair,
// with Simbody's matter, force, contact-tracking and compliant-contact subsystems, stepped as
// Gazebo's SimbodyPhysics steps it: commands written into the integrator's advanced state, then
// Integrator::stepTo(t, t) to the step's end. Commanded speeds are Simbody's prescribed motion
// (Motion::Steady): the engine computes the generalized force that realises them.
#include "engines/simbody/simbody_sim.hpp"

#include <Simbody.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace liftcheck::simbody {

namespace {

using namespace SimTK;

Vec3 to_vec3(const Eigen::Vector3d& v) { return Vec3(v.x(), v.y(), v.z()); }
Eigen::Vector3d from_vec3(const Vec3& v) { return Eigen::Vector3d(v[0], v[1], v[2]); }

std::unique_ptr<Integrator> make_integrator(const MultibodySystem& system, const IntegratorDef& def) {
  std::unique_ptr<Integrator> integ;
  if (def.method == "semi_explicit_euler2")
    integ = std::make_unique<SemiExplicitEuler2Integrator>(system);
  else if (def.method == "rk_merson")
    integ = std::make_unique<RungeKuttaMersonIntegrator>(system);
  else if (def.method == "rk3")
    integ = std::make_unique<RungeKutta3Integrator>(system);
  else
    throw std::invalid_argument("unknown Simbody integrator " + def.method);
  integ->setAccuracy(def.accuracy);
  return integ;
}

/// What every Simbody world here has: the subsystems in the order Gazebo creates them.
struct World {
  MultibodySystem system;
  SimbodyMatterSubsystem matter{system};
  GeneralForceSubsystem forces{system};
  ContactTrackerSubsystem tracker{system};
  CompliantContactSubsystem contact{system, tracker};
  std::unique_ptr<Integrator> integ;
  double t_s = 0.0;

  explicit World(const ContactDef& c) { contact.setTransitionVelocity(c.transition_velocity_mps); }
  ContactMaterial material(const ContactDef& c, double mu) const {
    return ContactMaterial(c.stiffness_Pa, c.dissipation_s_per_m, mu, mu, 0.0);  // static, dynamic, viscous
  }
  /// Topology realized, `init` sets the initial coordinates, the integrator starts there.
  template <class Init>
  void start(const IntegratorDef& def, Init init) {
    State s = system.realizeTopology();
    init(s);
    system.realize(s, Stage::Velocity);
    integ = make_integrator(system, def);
    integ->initialize(s);
  }
  /// After the caller changed the advanced state's free speeds or a Motion's rate (an Instance-stage
  /// variable): the prescribed speeds written into the state (System::prescribeU) and the
  /// integrator told the state changed from Instance on, so it reuses no derivative of the state
  /// before the change (Integrator::reinitialize's contract for a changed advanced state).
  void commit_changes() {
    State& s = integ->updAdvancedState();
    system.realize(s, Stage::Position);
    system.prescribeU(s);
    integ->reinitialize(Stage::Instance, false);
  }
  /// The integrator from t to t + dt, stopping exactly there (Gazebo: stepTo(t, t)).
  void advance(double dt_s) {
    t_s += dt_s;
    while (integ->getTime() < t_s) {
      const Integrator::SuccessfulStepStatus status = integ->stepTo(t_s, t_s);
      if (status == Integrator::EndOfSimulation || status == Integrator::InvalidSuccessfulStepStatus)
        throw std::runtime_error("Simbody's integrator stopped at t = " + std::to_string(integ->getTime()) + " s");
    }
  }
  const State& state() const {
    system.realize(integ->getState(), Stage::Velocity);
    return integ->getState();
  }
};

/// Inertia of a box (edges a, b, c) about its centre.
Inertia box_inertia(double m, double a, double b, double c) {
  return Inertia(m * (b * b + c * c) / 12.0, m * (a * a + c * c) / 12.0, m * (a * a + b * b) / 12.0);
}

}  // namespace

struct CarSim::Impl {
  explicit Impl(const CarDef& d) : def(d), world(d.contact) {}
  CarDef def;
  World world;
  Force::UniformGravity gravity;
  MobilizedBody::Free chassis;
  MobilizedBody::Pin knuckle, front, rear[2];
  /// The servos: the spin and steering speeds prescribed (Simbody computes the torque they take).
  Motion::Steady spin_motion, steer_motion;
  /// The brake of a braked run: each rear wheel's speed prescribed at 0 (a lock; unbuilt otherwise).
  Motion::Steady rear_brake[2];
};

CarSim::CarSim(const CarDef& d) : impl_(std::make_unique<Impl>(d)) {
  Impl& m = *impl_;
  World& w = m.world;
  m.gravity = Force::UniformGravity(w.forces, w.matter, to_vec3(d.gravity_W_mps2));
  const ContactMaterial mat = w.material(d.contact, d.mu);
  // Ground: a half-space (Simbody's occupies x > 0), turned so that it fills z < 0, as Gazebo's
  // SimbodyPhysics adds its ground plane.
  w.matter.updGround().updBody().addContactSurface(Transform(Rotation(Pi / 2, YAxis)),
                                                   ContactSurface(ContactGeometry::HalfSpace(), mat));

  // Chassis: the box's centre of mass l/2 behind the frame origin (MassProperties takes the
  // inertia about the body origin).
  const Vec3 com(-0.5 * d.l_m, 0.0, 0.0);
  const Inertia Ic = box_inertia(d.chassis_mass_kg, d.l_m, d.track_m, d.chassis_height_m);
  Body::Rigid chassis_body(MassProperties(d.chassis_mass_kg, com, Ic.shiftFromMassCenter(com, d.chassis_mass_kg)));
  m.chassis = MobilizedBody::Free(w.matter.updGround(), Transform(), chassis_body, Transform());

  // Steering knuckle: a Pin turns about the common z of its frames: the chassis z.
  const double Ik = d.knuckle_inertia_kgm2;
  Body::Rigid knuckle_body(MassProperties(d.knuckle_mass_kg, Vec3(0), Inertia(Ik, Ik, Ik)));
  m.knuckle = MobilizedBody::Pin(m.chassis, Transform(), knuckle_body, Transform());

  // Wheels: solid spheres; their Pins' z turned onto the axle y (Rotation(-pi/2, x) takes z to y),
  // so a positive spin rolls forward.
  const double Iw = 0.4 * d.wheel_mass_kg * d.R_m * d.R_m;
  Body::Rigid wheel_body(MassProperties(d.wheel_mass_kg, Vec3(0), Inertia(Iw, Iw, Iw)));
  wheel_body.addContactSurface(Transform(), ContactSurface(ContactGeometry::Sphere(d.R_m), mat));
  const Rotation z_to_y(-Pi / 2, XAxis);
  m.front = MobilizedBody::Pin(m.knuckle, Transform(z_to_y), wheel_body, Transform(z_to_y));
  for (int side = 0; side < 2; ++side) {
    const Vec3 hub(-d.l_m, (side == 0 ? 0.5 : -0.5) * d.track_m, 0.0);
    m.rear[side] = MobilizedBody::Pin(m.chassis, Transform(z_to_y, hub), wheel_body, Transform(z_to_y));
  }
  m.spin_motion = Motion::Steady(m.front, 0.0);
  m.steer_motion = Motion::Steady(m.knuckle, 0.0);
  if (d.rear_brake)
    for (int side = 0; side < 2; ++side) m.rear_brake[side] = Motion::Steady(m.rear[side], 0.0);

  w.start(d.integrator, [&](State& s) {
    m.chassis.setQToFitTransform(s, Transform(Rotation(d.phi0_rad, ZAxis), Vec3(d.x0_m, d.y0_m, d.R_m)));
    m.knuckle.setOneQ(s, 0, d.beta0_rad);
  });
}

CarSim::~CarSim() = default;

void CarSim::command(double spin_radps, double steer_radps) {
  Impl& m = *impl_;
  State& s = m.world.integ->updAdvancedState();
  m.spin_motion.setOneRate(s, MobilizerUIndex(0), spin_radps);
  m.steer_motion.setOneRate(s, MobilizerUIndex(0), steer_radps);
  m.world.commit_changes();
}

void CarSim::step(double dt_s) { impl_->world.advance(dt_s); }

CarOut CarSim::read() const {
  const Impl& m = *impl_;
  const State& s = m.world.state();
  CarOut out{};
  out.spin_joint_rad = m.front.getOneQ(s, 0);
  out.steer_rad = m.knuckle.getOneQ(s, 0);
  out.front_W = from_vec3(m.front.getBodyOriginLocation(s));
  const Rotation& Rc = m.chassis.getBodyRotation(s);
  out.phi_rad = std::atan2(Rc[1][0], Rc[0][0]);
  const MobilizedBody* wheels[3] = {&m.front, &m.rear[0], &m.rear[1]};
  for (int k = 0; k < 3; ++k) {
    const MobilizedBody& b = *wheels[k];
    // The wheel body's frame is its centre; its axle is the body y (the Pin's z turned onto it).
    out.wheels[k] = {from_vec3(b.getBodyOriginVelocity(s)), from_vec3(b.getBodyAngularVelocity(s)),
                     from_vec3(b.getBodyRotation(s) * Vec3(0, 1, 0)), b.getBodyOriginLocation(s)[2]};
  }
  out.rear_z_m = std::min(out.wheels[1].hub_z_m, out.wheels[2].hub_z_m);
  return out;
}

/// The tracker's active point contacts on `s` (realized to Dynamics), those that overlap.
static DisksContacts active_contacts(const World& w, const State& s) {
  w.system.realize(s, Stage::Dynamics);
  DisksContacts c;
  const ContactSnapshot& active = w.tracker.getActiveContacts(s);
  for (int k = 0; k < active.getNumContacts(); ++k) {
    const Contact& contact = active.getContact(k);
    if (!CircularPointContact::isInstance(contact)) continue;
    const double depth = CircularPointContact::getAs(contact).getDepth();
    if (depth < 0.0) continue;
    c.count += 1;
    c.depth_max_m = std::max(c.depth_max_m, depth);
  }
  return c;
}

struct DisksSim::Impl {
  explicit Impl(const DisksDef& d) : world(d.contact), radius_m(d.radius_m) {}
  World world;
  double radius_m;
  MobilizedBody::Translation M, N;
  Motion::Steady N_motion;
};

DisksSim::DisksSim(const DisksDef& d) : impl_(std::make_unique<Impl>(d)) {
  Impl& m = *impl_;
  World& w = m.world;
  const ContactMaterial mat = w.material(d.contact, d.mu_MN);
  const double I = 0.4 * d.mass_kg * d.radius_m * d.radius_m;
  Body::Rigid disk(MassProperties(d.mass_kg, Vec3(0), Inertia(I, I, I)));
  disk.addContactSurface(Transform(), ContactSurface(ContactGeometry::Sphere(d.radius_m), mat));
  m.M = MobilizedBody::Translation(w.matter.updGround(), Transform(), disk, Transform());
  m.N = MobilizedBody::Translation(w.matter.updGround(), Transform(), disk, Transform());
  m.N_motion = Motion::Steady(m.N, 0.0);
  w.start(d.integrator, [&](State& s) {
    m.M.setQToFitTranslation(s, Vec3(d.cM0_m.x(), d.cM0_m.y(), 0.0));
    m.N.setQToFitTranslation(s, Vec3(d.cN0_m.x(), d.cN0_m.y(), 0.0));
  });
}

DisksSim::~DisksSim() = default;

DisksContacts DisksSim::step(const Eigen::Vector2d& vM_mps, const Eigen::Vector2d& vN_mps, double dt_s) {
  Impl& m = *impl_;
  World& w = m.world;
  State& s = w.integ->updAdvancedState();
  m.M.setUToFitLinearVelocity(s, Vec3(vM_mps.x(), vM_mps.y(), 0.0));
  m.N_motion.setOneRate(s, MobilizerUIndex(0), vN_mps.x());
  m.N_motion.setOneRate(s, MobilizerUIndex(1), vN_mps.y());
  m.N_motion.setOneRate(s, MobilizerUIndex(2), 0.0);
  w.commit_changes();
  DisksContacts c = active_contacts(w, s);
  const double gap_m = (m.M.getBodyOriginLocation(s) - m.N.getBodyOriginLocation(s)).norm() - 2.0 * m.radius_m;
  w.advance(dt_s);
  if (c.count == 0) {
    c = active_contacts(w, w.state());
    if (c.count > 0) c.distance_min_m = gap_m, c.depth_max_m = 0.0;
  }
  return c;
}

Eigen::Vector2d DisksSim::cM() const {
  return from_vec3(impl_->M.getBodyOriginLocation(impl_->world.state())).head<2>();
}
Eigen::Vector2d DisksSim::cN() const {
  return from_vec3(impl_->N.getBodyOriginLocation(impl_->world.state())).head<2>();
}
Eigen::Vector3d DisksSim::wM_radps() const { return from_vec3(impl_->M.getBodyAngularVelocity(impl_->world.state())); }

}  // namespace liftcheck::simbody
