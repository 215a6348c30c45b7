// MuJoCo (libmujoco 2.2.x) in three configurations: its defaults as shipped, the defaults plus the
// noslip post-solver, and the stiffest contact refsafe allows with an elliptic cone and impratio 10.
//
// Every model is MJCF text built here and compiled by mj_loadXML from a virtual file system owned by
// the instance (no files on disk, no shared state). MuJoCo's warning handler is set once per process
// to write to stderr (as shipped it writes to stdout, which would corrupt --json output, and to
// MUJOCO_LOG.TXT in the user's folder); its error handler is left as shipped (it ends the process:
// running engines where they can be abandoned is the reliability work still to do). A bad state
// (its warnings for NaN in qpos, qvel or qacc) is reported as an engine error.
//
// Stepping is mj_step split in its two halves: mj_step2 integrates the state that the previous
// mj_step1 computed positions, velocities and contacts for (with the controls set in between), then
// mj_step1 runs kinematics and collision on the new state. So body poses, velocities and contacts
// read between steps describe the current state, and the contacts a step uses are those of the
// state it starts from. With the Euler integrator this is exactly mj_step.
//
// Car: the chassis carries a free joint whose origin is the front-axle centre (TricycleDef's
// chassis frame), a box of the chassis mass l/2 behind it (no collision); a steering knuckle hinged
// about the chassis z at the front-axle centre, the front wheel hinged about the knuckle's y; the
// rear wheels hinged about the chassis y. Wheels are spheres (condim 3) on a ground plane. Velocity
// actuators (force = kv (ctrl - qvel), limited to the servo's torque) realise the rate commands.
// Joint damping as the velocity term (which Euler integrates implicitly) is not used: MuJoCo applies
// it after the constraint solve, so the contact forces never see it and the driven wheel slips.
//
// Disks: M a sphere on two slide joints (x, y) with velocity actuators whose gain is M's mass / dt,
// so MuJoCo's Euler step realises the commanded velocity in one step when nothing pushes back;
// N a mocap sphere placed on its path each step. Both frictionless (condim 1), no gravity.
//
// Threads: each run owns its mjModel and mjData, so runs step in parallel. MuJoCo's process-wide
// state: mj_loadXML keeps the last compiled model for mj_saveLastXML behind its own mutex
// (xml_api.cc), and the warning handler mju_user_warning is one pointer, set under call_once before
// the first model in any thread and only read afterwards.
#include "engines/mujoco/mujoco_engine.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <mutex>
#include <fmt/format.h>
#include <memory>
#include <optional>
#include <string>

#include "engines/driven_disks.hpp"
#include "engines/rigid_car.hpp"
#include "models/e2.hpp"

namespace liftcheck {

namespace {

constexpr double kDefaultTimeconst_s = 0.02;  // MuJoCo's default solref (0.02, 1)

/// What a configuration changes from MuJoCo's defaults.
struct Variant {
  int noslip_iterations = 0;  ///< 0: MuJoCo's default (off)
  /// solref's time constant for every geom (MJCF <default><geom solref="timeconst 1"/>); none:
  /// refsafe's floor of 2 dt, the stiffest contact MuJoCo steps without clamping.
  std::optional<double> solref_timeconst_s = kDefaultTimeconst_s;
  bool elliptic = false;  ///< option cone: pyramidal (MuJoCo's default) or elliptic
  double impratio = 1.0;  ///< MuJoCo's default 1
};

// Velocity actuator gains: MuJoCo's Euler step treats an actuator's velocity term explicitly, so
// kv dt / I must stay well below 2 for the joint's own inertia I (a wheel that loses grip turns on
// that alone). kv = I / dt makes one step deadbeat for the unloaded joint: 72 N m s on the spin at
// R = 0.3 m and dt = 1 ms. Stiffer gains (kv dt / I = 2.8) made a sliding wheel's servo oscillate.
double spin_inertia(const TricycleDef& d) { return 0.4 * d.wheel_mass_kg * d.R_m * d.R_m; }
double steer_inertia(const TricycleDef& d) { return spin_inertia(d) + d.knuckle_inertia_kgm2(); }
constexpr double kDiskMass_kg = 1.0;
constexpr int kDefaultNoslip = 10;
constexpr double kDefaultImpratio = 10.0;

/// The variant with the knobs `s` declares for its vehicle applied.
Variant with_settings(Variant v, const Settings& s) {
  if (s.has("noslip_iterations")) v.noslip_iterations = s.integer("noslip_iterations");
  if (s.has("impratio")) v.impratio = s.number("impratio");
  if (s.has("solref_timeconst_s")) v.solref_timeconst_s = s.number("solref_timeconst_s");
  if (s.has("cone")) v.elliptic = s.choice("cone") == "elliptic";
  return v;
}

/// The variant's solref time constant at time step dt. MuJoCo's refsafe (on unless the option flag
/// refsafe is disabled, mjDSBL_REFSAFE: "make ref[0] >= 2*timestep") raises a smaller one to 2 dt
/// without a word, so the run would not be the one its record names: refused as bad input.
double solref_timeconst(const Variant& v, double dt) {
  const double floor_s = 2.0 * dt;
  const double tc = v.solref_timeconst_s.value_or(floor_s);
  if (tc < floor_s)
    throw InputError(
        fmt::format("setting 'solref_timeconst_s' = {:g} s is below 2 dt = {:g} s, the floor MuJoCo's refsafe raises "
                    "solref's time constant to "
                    "without a word: set at least {:g} s (or a smaller dt)",
                    tc, floor_s, floor_s));
  return tc;
}

/// The <option> element and the geom defaults of a variant at time step dt. Options left at
/// MuJoCo's defaults are not written; solref always is (MuJoCo's own default is 0.02 1).
std::string option_xml(const Variant& v, double dt, const Eigen::Vector3d& gravity_W_mps2) {
  std::string opt = fmt::format(R"(<option timestep="{:.17g}" gravity="{:.17g} {:.17g} {:.17g}")", dt,
                                gravity_W_mps2.x(), gravity_W_mps2.y(), gravity_W_mps2.z());
  if (v.noslip_iterations > 0) opt += fmt::format(R"( noslip_iterations="{}")", v.noslip_iterations);
  if (v.elliptic) opt += R"( cone="elliptic")";
  if (v.impratio != 1.0) opt += fmt::format(R"( impratio="{:.17g}")", v.impratio);
  opt += "/>\n";
  opt += fmt::format(R"(<default><geom solref="{:.17g} 1"/></default>)"
                     "\n",
                     solref_timeconst(v, dt));
  return opt;
}

/// MuJoCo's warnings go to stderr, set once per process before the first model is compiled.
void route_warnings() {
  static std::once_flag once;
  std::call_once(once,
                 [] { mju_user_warning = [](const char* msg) { std::fprintf(stderr, "MuJoCo warning: %s\n", msg); }; });
}

/// A compiled model and its data, owned together.
class Sim {
 public:
  explicit Sim(const std::string& xml) {
    route_warnings();
    // mjVFS holds its file table inline (a few MB): on the heap, one per model.
    auto vfs = std::make_unique<mjVFS>();
    mj_defaultVFS(vfs.get());
    const char* name = "liftcheck.xml";
    if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0)
      throw EngineError("MuJoCo: could not make the model file in the virtual file system");
    std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), name)], xml.data(), xml.size());
    char err[1000] = "";
    m_ = mj_loadXML(name, vfs.get(), err, sizeof err);
    mj_deleteVFS(vfs.get());
    if (!m_) throw EngineError(fmt::format("MuJoCo could not compile the model: {}", err));
    d_ = mj_makeData(m_);
    if (!d_) {
      mj_deleteModel(m_);
      throw EngineError("MuJoCo could not allocate its data");
    }
  }
  Sim(const Sim&) = delete;
  Sim& operator=(const Sim&) = delete;
  ~Sim() {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }

  mjModel* m() const { return m_; }
  mjData* d() const { return d_; }

  int id(mjtObj type, const char* name) const {
    const int i = mj_name2id(m_, type, name);
    if (i < 0) throw EngineError(fmt::format("MuJoCo model has no object named {}", name));
    return i;
  }

  /// Positions, velocities and contacts of the current state.
  void start() {
    mj_step1(m_, d_);
    check();
  }
  /// Integrates one step with the controls set, then computes the new state's kinematics and contacts.
  void step() {
    mj_step2(m_, d_);
    check();
  }
  void finish_step() {
    mj_step1(m_, d_);
    check();
  }

 private:
  void check() const {
    for (int w : {mjWARN_BADQPOS, mjWARN_BADQVEL, mjWARN_BADQACC})
      if (d_->warning[w].number > 0)
        throw EngineError(fmt::format("MuJoCo reported a bad state ({}) at t = {:.4f} s",
                                      w == mjWARN_BADQPOS   ? "qpos"
                                      : w == mjWARN_BADQVEL ? "qvel"
                                                            : "qacc",
                                      d_->time));
  }

  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
};

std::string num(double x) { return fmt::format("{:.17g}", x); }

class RawMujocoCar;

class MujocoCar final : public RigidCar {
  friend class RawMujocoCar;  // the benchmarks' raw loop on this model

 public:
  MujocoCar(const Settings& s, Variant v) : RigidCar(s), v_(with_settings(v, s)) {}

 protected:
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    const Variant& v = v_;
    beta0_ = q0.beta_rad;
    const std::string wheel_geom = fmt::format(
        R"(<geom type="sphere" size="{}" mass="{}" condim="3" friction="{} 0.005 0.0001" contype="1" conaffinity="2"/>)",
        num(d.R_m), num(d.wheel_mass_kg), num(setup.mu));
    const std::string xml = fmt::format(
        R"(<mujoco model="liftcheck tricycle">
{option}<worldbody>
<geom name="ground" type="plane" size="0 0 1" condim="3" friction="{mu} 0.005 0.0001" contype="2" conaffinity="1"/>
<body name="chassis" pos="{x} {y} {R}" quat="{qw} 0 0 {qz}">
  <freejoint name="chassis"/>
  <geom type="box" pos="{half_l_neg} 0 0" size="{half_l} {half_track} {half_h}" mass="{mc}" contype="0" conaffinity="0"/>
  <body name="knuckle" quat="{bw} 0 0 {bz}">
    <joint name="steer" type="hinge" axis="0 0 1"/>
    <inertial pos="0 0 0" mass="{mk}" diaginertia="{ik} {ik} {ik}"/>
    <body name="front">
      <joint name="spin" type="hinge" axis="0 1 0"/>
      {wheel}
    </body>
  </body>
  <body name="rear_left" pos="{l_neg} {half_track} 0">
    <joint name="rear_left" type="hinge" axis="0 1 0"/>
    {wheel}
  </body>
  <body name="rear_right" pos="{l_neg} {half_track_neg} 0">
    <joint name="rear_right" type="hinge" axis="0 1 0"/>
    {wheel}
  </body>
</body>
</worldbody>
<actuator>
<velocity name="spin" joint="spin" kv="{kv_spin}" forcelimited="true" forcerange="{tspin_neg} {tspin}"/>
<velocity name="steer" joint="steer" kv="{kv_steer}" forcelimited="true" forcerange="{tsteer_neg} {tsteer}"/>
{brakes}</actuator>
</mujoco>
)",
        fmt::arg("option", option_xml(v, setup.dt_s, setup.gravity_W())), fmt::arg("mu", num(setup.mu)),
        fmt::arg("x", num(q0.x_m)), fmt::arg("y", num(q0.y_m)), fmt::arg("R", num(d.R_m)),
        fmt::arg("qw", num(std::cos(0.5 * q0.phi_rad))), fmt::arg("qz", num(std::sin(0.5 * q0.phi_rad))),
        fmt::arg("half_l_neg", num(-0.5 * d.l_m)), fmt::arg("half_l", num(0.5 * d.l_m)),
        fmt::arg("half_track", num(0.5 * d.track_m)), fmt::arg("half_track_neg", num(-0.5 * d.track_m)),
        fmt::arg("half_h", num(0.5 * d.chassis_height_m)), fmt::arg("mc", num(d.chassis_mass_kg)),
        fmt::arg("bw", num(std::cos(0.5 * q0.beta_rad))), fmt::arg("bz", num(std::sin(0.5 * q0.beta_rad))),
        fmt::arg("mk", num(d.knuckle_mass_kg)), fmt::arg("ik", num(d.knuckle_inertia_kgm2())),
        fmt::arg("wheel", wheel_geom), fmt::arg("l_neg", num(-d.l_m)),
        fmt::arg("kv_spin", num(spin_inertia(d) / setup.dt_s)),
        fmt::arg("kv_steer", num(steer_inertia(d) / setup.dt_s)), fmt::arg("tspin", num(servo_.spin_torque_max_Nm)),
        fmt::arg("tspin_neg", num(-servo_.spin_torque_max_Nm)), fmt::arg("tsteer", num(servo_.steer_torque_max_Nm)),
        fmt::arg("tsteer_neg", num(-servo_.steer_torque_max_Nm)), fmt::arg("brakes", brakes_xml(d, setup.dt_s)));
    sim_.reset();
    sim_ = std::make_unique<Sim>(xml);
    const mjModel* m = sim_->m();
    chassis_ = sim_->id(mjOBJ_BODY, "chassis");
    wheel_[0] = sim_->id(mjOBJ_BODY, "front");
    wheel_[1] = sim_->id(mjOBJ_BODY, "rear_left");
    wheel_[2] = sim_->id(mjOBJ_BODY, "rear_right");
    spin_qpos_ = m->jnt_qposadr[sim_->id(mjOBJ_JOINT, "spin")];
    steer_qpos_ = m->jnt_qposadr[sim_->id(mjOBJ_JOINT, "steer")];
    spin_act_ = sim_->id(mjOBJ_ACTUATOR, "spin");
    steer_act_ = sim_->id(mjOBJ_ACTUATOR, "steer");
    ground_ = sim_->id(mjOBJ_GEOM, "ground");
    sim_->start();
  }

  /// The brake of a braked run (ServoDef::rear_brake_torque_max_Nm > 0; none otherwise): a velocity
  /// actuator on each rear wheel's hinge, as the front spin's (kv = the wheel's own inertia / dt,
  /// force-limited to the brake's torque), its ctrl left at 0: MuJoCo's documented <velocity>
  /// actuator, force = kv (ctrl - qvel).
  std::string brakes_xml(const TricycleDef& d, double dt_s) const {
    const double t = servo_.rear_brake_torque_max_Nm;
    if (!(t > 0.0)) return "";
    std::string xml;
    for (const char* joint : {"rear_left", "rear_right"})
      xml +=
          fmt::format(R"(<velocity name="brake_{j}" joint="{j}" kv="{kv}" forcelimited="true" forcerange="{lo} {hi}"/>)"
                      "\n",
                      fmt::arg("j", joint), fmt::arg("kv", num(spin_inertia(d) / dt_s)), fmt::arg("lo", num(-t)),
                      fmt::arg("hi", num(t)));
    return xml;
  }

  void actuate(const FrontRates& rates, const ServoDef&) override {
    const double spin_radps = rates.spin_radps[0], steer_radps = rates.steer_radps[0];
    sim_->d()->ctrl[spin_act_] = spin_radps;
    sim_->d()->ctrl[steer_act_] = steer_radps;
  }

  void step(double) override {
    sim_->step();
    // Between mj_step2 and mj_step1 the contacts and their solved forces (efc_force) are those that
    // acted during the step just taken; mj_step1 then builds the new state's.
    ground_force_W_ = ground_force(sim_->m(), sim_->d());
    sim_->finish_step();
  }

  std::optional<Eigen::Vector3d> ground_force_W() const override { return ground_force_W_; }

  /// The ground plane's contacts' forces on the wheels (mj_contactForce: normal then tangential
  /// components in the contact frame, whose first row is the normal from geom1 towards geom2, the
  /// force acting on geom2).
  Eigen::Vector3d ground_force(const mjModel* m, const mjData* d) const {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int i = 0; i < d->ncon; ++i) {
      const mjContact& c = d->contact[i];
      if (c.geom1 != ground_ && c.geom2 != ground_) continue;
      mjtNum f[6];
      mj_contactForce(m, d, i, f);
      const Eigen::Vector3d f_W = f[0] * Eigen::Vector3d(c.frame[0], c.frame[1], c.frame[2]) +
                                  f[1] * Eigen::Vector3d(c.frame[3], c.frame[4], c.frame[5]) +
                                  f[2] * Eigen::Vector3d(c.frame[6], c.frame[7], c.frame[8]);
      sum += c.geom2 == ground_ ? -f_W : f_W;
    }
    return sum;
  }

  RigidCarState read() const override {
    const mjModel* m = sim_->m();
    const mjData* d = sim_->d();
    const mjtNum* front = d->xpos + 3 * wheel_[0];
    const mjtNum* rot = d->xmat + 9 * chassis_;  // row-major: world = rot * body
    RigidCarState st{};
    st.spin_joint_rad[0] = e2::wrap_angle(d->qpos[spin_qpos_]);
    st.steer_rad[0] = beta0_ + d->qpos[steer_qpos_];
    st.x_m = front[0];
    st.y_m = front[1];
    st.z_m = front[2];
    st.phi_rad = std::atan2(rot[3], rot[0]);
    st.rear_z_m = std::min(d->xpos[3 * wheel_[1] + 2], d->xpos[3 * wheel_[2] + 2]);
    for (int w = 0; w < 3; ++w) {
      const int b = wheel_[w];
      mjtNum vel[6];  // angular, linear; world axes, at the body's centre of mass (the wheel centre)
      mj_objectVelocity(m, d, mjOBJ_BODY, b, vel, 0);
      const mjtNum* r = d->xmat + 9 * b;
      st.wheels[w] = {Eigen::Vector3d(vel[3], vel[4], vel[5]), Eigen::Vector3d(vel[0], vel[1], vel[2]),
                      Eigen::Vector3d(r[1], r[4], r[7]).normalized(),  // the body's y axis: the hinge axis
                      d->xpos[3 * b + 2]};
    }
    mjtNum vc[6];  // mjOBJ_BODY: at the chassis's centre of mass (xipos), world axes
    mj_objectVelocity(m, d, mjOBJ_BODY, chassis_, vc, 0);
    st.v_chassis_W = {vc[3], vc[4], vc[5]};
    return st;
  }

 private:
  Variant v_;
  std::unique_ptr<Sim> sim_;
  double beta0_ = 0.0;
  int chassis_ = -1, wheel_[3] = {-1, -1, -1};
  int spin_qpos_ = -1, steer_qpos_ = -1, spin_act_ = -1, steer_act_ = -1, ground_ = -1;
  Eigen::Vector3d ground_force_W_ = Eigen::Vector3d::Zero();
};

class MujocoDisks final : public DrivenDisks {
 public:
  MujocoDisks(const Settings& s, Variant v) : v_(with_settings(v, s)) {}

 protected:
  void build(const DiskSetup& setup, const disks::Vec2& cM0, const disks::Vec2& cN0) override {
    const double kv = kDiskMass_kg / setup.dt_s;  // one Euler step: v' = v + dt (kv / m)(v_cmd - v) = v_cmd
    const std::string xml = fmt::format(
        R"(<mujoco model="liftcheck disks">
{option}<worldbody>
<body name="M" pos="{mx} {my} 0">
  <joint name="x" type="slide" axis="1 0 0"/>
  <joint name="y" type="slide" axis="0 1 0"/>
  <geom type="sphere" size="{r}" mass="{mass}" condim="{condim}" friction="{mu} 0 0"/>
</body>
<body name="N" mocap="true" pos="{nx} {ny} 0">
  <geom type="sphere" size="{r}" condim="{condim}" friction="{mu} 0 0"/>
</body>
</worldbody>
<actuator>
<velocity name="x" joint="x" kv="{kv}"/>
<velocity name="y" joint="y" kv="{kv}"/>
</actuator>
</mujoco>
)",
        fmt::arg("option", option_xml(v_, setup.dt_s, Eigen::Vector3d::Zero())), fmt::arg("mx", num(cM0.x())),
        fmt::arg("my", num(cM0.y())), fmt::arg("nx", num(cN0.x())), fmt::arg("ny", num(cN0.y())),
        fmt::arg("r", num(setup.radius_m)), fmt::arg("mass", num(kDiskMass_kg)), fmt::arg("kv", num(kv)),
        // Frictionless (condim 1) in every scenario; with friction mu_MN, condim 3 (MuJoCo takes the
        // larger condim and friction of the two geoms).
        fmt::arg("condim", setup.mu_MN > 0.0 ? 3 : 1), fmt::arg("mu", num(setup.mu_MN)));
    sim_.reset();
    sim_ = std::make_unique<Sim>(xml);
    M_ = sim_->id(mjOBJ_BODY, "M");
    N_ = sim_->id(mjOBJ_BODY, "N");
    mocap_ = sim_->m()->body_mocapid[N_];
    gM_ = sim_->m()->body_geomadr[M_];
    gN_ = sim_->m()->body_geomadr[N_];
    ax_ = sim_->id(mjOBJ_ACTUATOR, "x");
    ay_ = sim_->id(mjOBJ_ACTUATOR, "y");
    sim_->start();
  }

  StepContacts step(const disks::Vec2& vM_cmd, const disks::Vec2& cN_next, const disks::Vec2&, double) override {
    mjData* d = sim_->d();
    // The contacts this step uses: those mj_step1 generated on the state at its start.
    StepContacts c;
    for (int i = 0; i < d->ncon; ++i) {
      const mjContact& k = d->contact[i];
      const bool pair = (k.geom1 == gM_ && k.geom2 == gN_) || (k.geom1 == gN_ && k.geom2 == gM_);
      if (!pair || k.dist > 0) continue;
      c.count += 1;
      c.depth_max_m = std::max(c.depth_max_m, -k.dist);
    }
    d->ctrl[ax_] = vM_cmd.x();
    d->ctrl[ay_] = vM_cmd.y();
    sim_->step();
    // N moves along its path: the mocap body is placed, then the new state's kinematics and contacts.
    d->mocap_pos[3 * mocap_ + 0] = cN_next.x();
    d->mocap_pos[3 * mocap_ + 1] = cN_next.y();
    d->mocap_pos[3 * mocap_ + 2] = 0.0;
    sim_->finish_step();
    return c;
  }

  State read() const override {
    const mjtNum* x = sim_->d()->xpos;
    const mjtNum* w = sim_->d()->cvel + 6 * M_;  // [rotation; translation], the rotation in the world frame
    return {{x[3 * M_], x[3 * M_ + 1]}, {x[3 * N_], x[3 * N_ + 1]}, {w[0], w[1], w[2]}};
  }

 private:
  Variant v_;
  std::unique_ptr<Sim> sim_;
  int M_ = -1, N_ = -1, mocap_ = -1, gM_ = -1, gN_ = -1, ax_ = -1, ay_ = -1;
};

std::string version() { return fmt::format("{} (header {})", mj_versionString(), mjVERSION_HEADER); }

const char* const kServo =
    "MuJoCo velocity actuators (force = kv (ctrl - qvel), explicit in the Euler step) on the spin and steering hinges, "
    "kv = I / dt "
    "for the joint's own inertia I (deadbeat when unloaded: 72 N m s at R = 0.3 m, dt = 1 ms), force limited to the "
    "servo's torque limit (1.5 mu N R of the driven wheel, 106 N m for the default car); "
    "ctrl = commanded rate + 40/s x angle error; settle 0.5 s, hold 0.2 s";
const char* const kJoints =
    "chassis: free joint at the front-axle centre (box of the scenario's chassis_mass l/2 behind it, no collision); "
    "steering knuckle (knuckle_mass, isotropic inertia knuckle_mass x 2e-3 m^2) hinged "
    "about the chassis z at the front-axle centre; front wheel hinged about the knuckle's y; rear wheels hinged about "
    "the chassis y";
const char* const kStepping =
    "mj_step1 / set ctrl / mj_step2 (equal to mj_step); Euler integrator (MuJoCo's default), Newton solver, 100 "
    "iterations, tolerance 1e-8";
const char* const kDisks =
    "M: sphere (radius 1, 1 kg) on slide joints x and y, velocity actuators kv = 1 kg / dt (one Euler step realises "
    "the command); "
    "N: mocap sphere placed on its path each step; no gravity, frictionless (condim 1); first contact from the "
    "contacts mj_step1 "
    "generated on the state a step starts from (dist <= 0); the configuration's contact options apply";

std::vector<std::pair<std::string, std::string>> common_settings(const std::string& contact, const std::string& cone) {
  return {{"model", "MJCF built in code, compiled by mj_loadXML from an in-memory virtual file system"},
          {"stepping", kStepping},
          {"timestep", "the scenario's dt (option timestep)"},
          {"joints", kJoints},
          {"wheels",
           "spheres of radius R, 2 kg, condim 3, friction mu (torsional 0.005 and rolling 1e-4 unused at condim 3); "
           "ground plane, friction mu (MuJoCo takes the larger)"},
          {"contact", contact},
          {"friction cone", cone},
          {"contact forces",
           "mj_contactForce on every wheel-ground contact of the step just solved (read between mj_step2 and "
           "mj_step1), turned to the world frame (the load and momentum checks)"},
          {"servo", kServo},
          {"disks", kDisks}};
}

/// The benchmarks' raw loop (engines/raw_car.hpp): MujocoCar's compiled model and data, the
/// controls set once, mj_step directly.
class RawMujocoCar final : public RawCar {
 public:
  RawMujocoCar(const Settings& s, Variant v, const CarSetup& setup, const car::Config& q0) : car_(s, v) {
    car_.reset(setup, q0);
  }

  void run(long steps, double spin_radps) override {
    const mjModel* m = car_.sim_->m();
    mjData* d = car_.sim_->d();
    d->ctrl[car_.spin_act_] = spin_radps;
    d->ctrl[car_.steer_act_] = 0.0;
    for (long k = 0; k < steps; ++k) mj_step(m, d);
  }

  Eigen::Vector2d front_xy_m() const override {
    const mjtNum* p = car_.sim_->d()->xpos + 3 * car_.wheel_[0];
    return {p[0], p[1]};
  }

 private:
  MujocoCar car_;
};

const Variant kShipped{};
const Variant kNoslip{.noslip_iterations = kDefaultNoslip};
const Variant kStiff{.solref_timeconst_s = std::nullopt, .elliptic = true, .impratio = kDefaultImpratio};

/// The contact settings of the configurations at MuJoCo's default contact (mujoco, mujoco-noslip):
/// solref's time constant for both vehicles (the disks touch through it too), the friction cone
/// for the car only (the disks are frictionless, condim 1: the cone has nothing to shape there).
std::vector<SettingSpec> soft_contact_knobs() {
  std::vector<SettingSpec> knobs;
  for (const Vehicle vehicle : kVehicles)
    knobs.push_back({{.key = "solref_timeconst_s",
                      .kind = ParamKind::kNumber,
                      .default_text = fmt::format("{:g}", kDefaultTimeconst_s),
                      .unit = "s",
                      .help = "time constant of the contacts' soft constraint: solref[0] of the geom defaults (MJCF "
                              "<default><geom solref=\"timeconst 1\"/>, "
                              "MuJoCo's default 0.02 s), damping ratio kept at 1; at least 2 dt, refsafe's floor, to "
                              "which MuJoCo would raise a smaller one without a word",
                      .min = 0.0,
                      .min_exclusive = true,
                      .max = 1.0},
                     vehicle});
  knobs.push_back({{.key = "cone",
                    .kind = ParamKind::kChoice,
                    .default_text = "pyramidal",
                    .help = "friction cone (option cone): pyramidal, MuJoCo's default, or elliptic",
                    .choices = {"pyramidal", "elliptic"}},
                   Vehicle::kCar});
  return knobs;
}

const char* const kSoftContact =
    "solref (solref_timeconst_s, 1): the geom defaults' time constant, --set solref_timeconst_s for cars and disks "
    "(default 0.02 s, MuJoCo's; "
    "refused below 2 dt, refsafe's floor), damping ratio 1; solimp 0.9 0.95 0.001 (MuJoCo's default), margin 0";
const char* const kSoftCone =
    "car --set cone (default pyramidal, MuJoCo's; elliptic); disks frictionless; impratio 1 (MuJoCo's default)";

}  // namespace

std::unique_ptr<RawCar> make_raw_mujoco_car(const Settings& s, const CarSetup& setup, const car::Config& q0) {
  return std::make_unique<RawMujocoCar>(s, kShipped, setup, q0);
}
std::unique_ptr<RawCar> make_raw_mujoco_noslip_car(const Settings& s, const CarSetup& setup, const car::Config& q0) {
  return std::make_unique<RawMujocoCar>(s, kNoslip, setup, q0);
}
std::unique_ptr<RawCar> make_raw_mujoco_stiff_car(const Settings& s, const CarSetup& setup, const car::Config& q0) {
  return std::make_unique<RawMujocoCar>(s, kStiff, setup, q0);
}

EngineInfo mujoco_engine() {
  auto settings = common_settings(kSoftContact, kSoftCone);
  settings.push_back({"noslip", "off (noslip_iterations 0, MuJoCo's default)"});
  return {.name = "mujoco",
          .library = "MuJoCo",
          .version = version(),
          .description =
              "MuJoCo as shipped: MJCF tricycle with a free-joint chassis, hinge wheels, velocity actuators; Euler, "
              "Newton, pyramidal cone, soft contacts (solref 0.02 1)",
          .color = "#2ca02c",
          .make_car = [](const Settings& s) { return std::make_unique<MujocoCar>(s, kShipped); },
          .make_disks = [](const Settings& s) { return std::make_unique<MujocoDisks>(s, kShipped); },
          .contact_dynamics = true,
          .settings = settings,
          .knobs = soft_contact_knobs(),
          .brakes = true,
          .make_raw_car = make_raw_mujoco_car};
}

EngineInfo mujoco_noslip_engine() {
  auto settings = common_settings(kSoftContact, kSoftCone);
  settings.push_back({"noslip", fmt::format("noslip post-solver: car --set noslip_iterations (default {}); disks {} "
                                            "(frictionless, so it has no friction rows to act on)",
                                            kDefaultNoslip, kDefaultNoslip)});
  std::vector<SettingSpec> knobs = {
      SettingSpec{{.key = "noslip_iterations",
                   .kind = ParamKind::kInteger,
                   .default_text = std::to_string(kDefaultNoslip),
                   .unit = "1",
                   .help = "noslip post-solver iterations (option noslip_iterations; 0 turns it off)",
                   .min = 0,
                   .max = 1000},
                  Vehicle::kCar}};
  for (SettingSpec& k : soft_contact_knobs()) knobs.push_back(std::move(k));
  return {.name = "mujoco-noslip",
          .library = "MuJoCo",
          .version = version(),
          .description =
              "MuJoCo's defaults plus the noslip post-solver (10 iterations), the remedy MuJoCo's documentation names "
              "for slip",
          .color = "#98df8a",
          .make_car = [](const Settings& s) { return std::make_unique<MujocoCar>(s, kNoslip); },
          .make_disks = [](const Settings& s) { return std::make_unique<MujocoDisks>(s, kNoslip); },
          .contact_dynamics = true,
          .settings = settings,
          .knobs = knobs,
          .brakes = true,
          .make_raw_car = make_raw_mujoco_noslip_car};
}

// No solref_timeconst_s here: this configuration's time constant is 2 dt of the run's own dt, which
// no fixed default value states (and any smaller one refsafe would clamp).
EngineInfo mujoco_stiff_engine() {
  auto settings = common_settings(
      "solref (2 dt, 1): time constant at its refsafe floor of 2 x timestep (0.002 at 1 ms), damping ratio 1; solimp "
      "0.9 0.95 0.001 (default), margin 0",
      fmt::format("elliptic; impratio: car --set impratio (default {:g}), disks {:g}", kDefaultImpratio,
                  kDefaultImpratio));
  settings.push_back({"noslip", "off (noslip_iterations 0, MuJoCo's default)"});
  return {.name = "mujoco-stiff",
          .library = "MuJoCo",
          .version = version(),
          .description =
              "MuJoCo with the stiffest contacts refsafe allows (solref 2 dt), elliptic friction cone, impratio 10",
          .color = "#006d2c",
          .make_car = [](const Settings& s) { return std::make_unique<MujocoCar>(s, kStiff); },
          .make_disks = [](const Settings& s) { return std::make_unique<MujocoDisks>(s, kStiff); },
          .contact_dynamics = true,
          .settings = settings,
          .knobs = {SettingSpec{{.key = "impratio",
                                 .kind = ParamKind::kNumber,
                                 .default_text = fmt::format("{:g}", kDefaultImpratio),
                                 .unit = "1",
                                 .help = "ratio of frictional to normal constraint impedance (option impratio)",
                                 .min = 0.0,
                                 .min_exclusive = true,
                                 .max = 1000.0},
                                Vehicle::kCar}},
          .brakes = true,
          .make_raw_car = make_raw_mujoco_stiff_car};
}

}  // namespace liftcheck
