// Rapier (@dimforge/rapier3d-compat, Rust compiled to WASM, float32) served over liftcheck's
// engine protocol (docs/protocol.md).
//
// Car: rigid bodies for the chassis (a cuboid collider that collides with nothing), the steering
// knuckle(s) (mass properties only) and ball wheels; revolute impulse joints for the steering
// (chassis z) and the wheels (knuckle y, chassis y), velocity motors on each front wheel's steering
// and spin (Rapier's JS multibody joints have no motors), and in a braked run on each rear wheel's
// spin joint (target 0, limited to the brake's torque); the tricycle or the four-wheel car. The
// ground is a cuboid under the start.
// Disks: M a dynamic ball whose linear velocity is set to the command before each step, N a
// kinematic position-based ball given its next translation; the contacts are the points of the
// M-N contact manifold the narrow phase built in the step, predictive ones included.
//
//   node rapier.mjs --config default|accurate
// default: Rapier's integration parameters as shipped (4 solver iterations, 1 internal PGS
// iteration); accurate: 16 solver iterations, following the documentation of
// World.numSolverIterations ("the greater this value is, the most rigid and realistic the
// physics simulation will be").
import RAPIER from '@dimforge/rapier3d-compat';

import { serve, timed } from './protocol.mjs';
import * as C from './common.mjs';

console.log = console.error;  // the WASM loader's notices must not reach standard output
await RAPIER.init();
const VERSION = RAPIER.version();
const CONFIGS = { default: { solver: 4, pgs: 1 }, accurate: { solver: 16, pgs: 1 } };
const opts = C.parseArgs(process.argv.slice(2), CONFIGS);
const CONFIG = CONFIGS[opts.config];
const KNOBS = [
  { key: 'iterations', vehicle: 'car', kind: 'integer', role: 'solver_iterations', min: 1, max: 1000, default: String(CONFIG.solver),
    help: 'solver iterations (substeps) per step (World.numSolverIterations)' },
  { key: 'pgs_iterations', vehicle: 'car', kind: 'integer', role: 'solver_iterations', min: 1, max: 1000, default: String(CONFIG.pgs),
    help: 'internal PGS iterations per solver iteration (World.numInternalPgsIterations)' },
];
// A velocity motor as a stiff damper: AccelerationBased, factor 100/dt (the constraint's
// softness dt x factor is 100, so one step realises 99% of the rate change) under the torque limit.
const MOTOR_FACTOR_DT = 100;
const GROUND_HALF_M = 50;  // the ground cuboid's half side, centred under the start
const GROUND = 0x0001, WHEEL = 0x0002;
const groups = (member, filter) => (member << 16) | filter;

const v3 = (a) => ({ x: a[0], y: a[1], z: a[2] });
const arr = (v) => [v.x, v.y, v.z];
const q4 = (q) => ({ x: q[0], y: q[1], z: q[2], w: q[3] });
const quat = (b) => { const r = b.rotation(); return [r.x, r.y, r.z, r.w]; };
let car = null, disks = null, world = null;

function newWorld(gravity_W, dt_s) {
  if (world) world.free();
  world = new RAPIER.World(v3(gravity_W));
  world.timestep = dt_s;
  return world;
}

function dynamic(p, q) {
  return world.createRigidBody(RAPIER.RigidBodyDesc.dynamic().setTranslation(...p).setRotation(q4(q)).setCanSleep(false));
}

function revolute(a, b, anchorA, axis, motorMax_Nm) {
  const j = world.createImpulseJoint(RAPIER.JointData.revolute(v3(anchorA), v3([0, 0, 0]), v3(axis)), a, b, true);
  if (motorMax_Nm) {
    j.configureMotorModel(RAPIER.MotorModel.AccelerationBased);
    j.setMotorMaxForce(motorMax_Nm);
    j.configureMotorVelocity(0, MOTOR_FACTOR_DT / world.timestep);
  }
  return j;
}

function buildCar(req) {
  car = disks = null;  // a build that fails leaves no world to step
  const s = C.applySettings(KNOBS, req.settings, 'car');
  const { car: d, q0, servo, mu, dt_s, gravity_W } = C.carRequest(req);
  newWorld(gravity_W, dt_s);
  world.numSolverIterations = s.iterations;
  world.numInternalPgsIterations = s.pgs_iterations;
  // Friction: Rapier averages the two colliders' coefficients by default; both are mu.
  world.createCollider(RAPIER.ColliderDesc.cuboid(GROUND_HALF_M, GROUND_HALF_M, 0.5).setTranslation(q0.x_m, q0.y_m, -0.5)
    .setFriction(mu).setRestitution(0).setCollisionGroups(groups(GROUND, WHEEL)));
  const R = d.R_m, l = d.l_m, w = d.track_m;
  const yaw = C.yawQuat(q0.phi_rad);
  const chassis = dynamic(C.chassisPoint(q0, -l / 2, 0, R), yaw);
  world.createCollider(RAPIER.ColliderDesc.cuboid(l / 2, w / 2, d.chassis_height_m / 2).setMass(d.chassis_mass_kg).setCollisionGroups(0), chassis);
  const k2 = d.knuckle_mass_kg * C.KNUCKLE_GYRATION_SQ_M2;
  const wheel = (p, q) => {
    const b = dynamic(p, q);
    world.createCollider(RAPIER.ColliderDesc.ball(R).setMass(d.wheel_mass_kg).setFriction(mu).setRestitution(0).setCollisionGroups(groups(WHEEL, GROUND)), b);
    return b;
  };
  // Each front wheel on its knuckle: steering joint about the chassis z, spin joint about the knuckle y.
  const fronts = C.frontWheels(d, q0.beta_rad).map(({ y_m, beta0_rad }) => {
    const at = C.chassisPoint(q0, 0, y_m, R), q = C.yawQuat(q0.phi_rad + beta0_rad);
    const knuckle = world.createRigidBody(RAPIER.RigidBodyDesc.dynamic().setTranslation(...at).setRotation(q4(q)).setCanSleep(false)
      .setAdditionalMassProperties(d.knuckle_mass_kg, v3([0, 0, 0]), v3([k2, k2, k2]), q4([0, 0, 0, 1])));
    const wheelBody = wheel(at, q);
    return { knuckle, wheel: wheelBody, steer: revolute(chassis, knuckle, [l / 2, y_m, 0], [0, 0, 1], servo.steer_Nm),
      spin: revolute(knuckle, wheelBody, [0, 0, 0], [0, 1, 0], servo.spin_Nm) };
  });
  // The brake of a braked run (servo.rear_brake_Nm > 0, docs/protocol.md): each rear wheel's
  // revolute joint gets the same velocity motor as the front spin's (revolute() above:
  // configureMotorModel(AccelerationBased), setMotorMaxForce(the brake's torque, as the front spin
  // is given servo.spin_Nm), configureMotorVelocity(0, factor/dt), re-set each step in stepCar),
  // its target the zero rate of the wheel relative to the chassis. Rapier's joint motors: "Joint
  // motors" of the JavaScript user guide, https://rapier.rs/docs/user_guides/javascript/joints#joint-motors
  // (UnitImpulseJoint.configureMotorVelocity(targetVel, factor), setMotorMaxForce(maxForce),
  // configureMotorModel; rapier3d-compat 0.21.0, dist/dynamics/impulse_joint.d.ts). Unbraked (0):
  // the plain revolute joints as before, no motor.
  const brakes = [];
  const rears = [1, -1].map((s) => {
    const b = wheel(C.chassisPoint(q0, -l, s * w / 2, R), yaw);
    const j = revolute(chassis, b, [-l / 2, s * w / 2, 0], [0, 1, 0], servo.rear_brake_Nm);
    if (servo.rear_brake_Nm > 0) brakes.push(j);
    return b;
  });
  car = { chassis, fronts, rears, brakes };
  return carState(0);
}

const state = (b) => ({ p: arr(b.translation()), q: quat(b), v: arr(b.linvel()), w: arr(b.angvel()) });

function carState(engine_s) {
  const { chassis, fronts, rears } = car;
  return C.carReply(engine_s, fronts.map((f) => C.twist(quat(f.knuckle), quat(f.wheel), 1)),
    fronts.map((f) => C.twist(quat(chassis), quat(f.knuckle), 2)), quat(chassis), fronts.map((f) => state(f.wheel)), rears.map(state));
}

function stepCar(req) {
  const { spin, steer, dt_s } = C.carStep(req);
  if (dt_s !== world.timestep) world.timestep = dt_s;
  const factor = MOTOR_FACTOR_DT / dt_s;
  car.fronts.forEach((f, k) => {  // the rate of the second body relative to the first
    f.spin.configureMotorVelocity(spin[k], factor);
    f.steer.configureMotorVelocity(steer[k], factor);
  });
  for (const j of car.brakes) j.configureMotorVelocity(0, factor);  // braked: rear wheels at zero rate against the chassis
  return carState(timed(() => world.step()));
}

function buildDisks(req) {
  car = disks = null;
  C.applySettings(KNOBS, req.settings, 'disks');
  const { radius_m, dt_s, cM0, cN0, mu_MN } = C.diskRequest(req);
  newWorld([0, 0, 0], dt_s);
  world.numSolverIterations = CONFIG.solver;
  world.numInternalPgsIterations = CONFIG.pgs;
  const M = world.createRigidBody(RAPIER.RigidBodyDesc.dynamic().setTranslation(cM0[0], cM0[1], 0).enabledTranslations(true, true, false).lockRotations().setCanSleep(false));
  const N = world.createRigidBody(RAPIER.RigidBodyDesc.kinematicPositionBased().setTranslation(cN0[0], cN0[1], 0));
  // Friction mu_MN on both (Rapier's Average combine): 0, frictionless, in every scenario.
  const ball = () => RAPIER.ColliderDesc.ball(radius_m).setFriction(mu_MN).setRestitution(0);
  const colM = world.createCollider(ball().setMass(1), M), colN = world.createCollider(ball(), N);
  disks = { M, N, colM, colN };
  car = null;
  return diskPositions();
}

function diskPositions() {
  const m = disks.M.translation(), n = disks.N.translation(), w = disks.M.angvel();
  return { cM: [m.x, m.y], cN: [n.x, n.y], wM: [w.x, w.y, w.z] };
}

const pose = (b) => { const t = b.translation(), r = b.rotation(); return { x: [t.x, t.y, t.z], q: [r.x, r.y, r.z, r.w] }; };
const at = (p, l) => C.rotate(p.q, [l.x, l.y, l.z]).map((v, j) => v + p.x[j]);

/// The M-N contacts of the step with their signed distances on the start state. Rapier's narrow
/// phase keeps a manifold's points between its updates (contactDist is their distance when last
/// computed) and its solver measures each point's distance from the two local points anchored to
/// the bodies: so here, n . (p2 - p1) with both points at the poses the step started from.
function diskContacts(start) {
  const contacts = { count: 0, depth_max_m: 0, distance_min_m: 0 };
  let dmin = Infinity;
  world.contactPair(disks.colM, disks.colN, (manifold, flipped) => {
    const [a, b] = flipped ? [start.N, start.M] : [start.M, start.N];
    const n1 = manifold.localNormal1(), n = C.rotate(a.q, [n1.x, n1.y, n1.z]);
    for (let i = 0; i < manifold.numContacts(); i++) {
      const p1 = at(a, manifold.localContactPoint1(i)), p2 = at(b, manifold.localContactPoint2(i));
      dmin = Math.min(dmin, n[0] * (p2[0] - p1[0]) + n[1] * (p2[1] - p1[1]) + n[2] * (p2[2] - p1[2]));
      contacts.count += 1;
    }
  });
  if (contacts.count > 0) Object.assign(contacts, { distance_min_m: dmin, depth_max_m: Math.max(0, -dmin) });
  return contacts;
}

function stepDisks(req) {
  const { vM, cN_next, dt_s } = C.diskStep(req);
  if (dt_s !== world.timestep) world.timestep = dt_s;
  const start = { M: pose(disks.M), N: pose(disks.N) };
  disks.M.setLinvel(v3([vM[0], vM[1], 0]), true);
  disks.N.setNextKinematicTranslation(v3([cN_next[0], cN_next[1], 0]));
  const engine_s = timed(() => world.step());
  return { engine_s, ...diskPositions(), contacts: diskContacts(start) };
}

serve({
  hello: () => ({
    engine: 'Rapier', version: VERSION, precision: 'float32', vehicles: ['car', 'disks'], four_wheels: true, brakes: true, settings: KNOBS,
    fixed: [
      ['stepping', 'World.step() with World.timestep = dt (no interpolation); integration parameters otherwise as shipped: read back from rapier3d-compat 0.21.0, prediction distance 0.02 m, allowed linear error 0.005 m (normalizedAllowedLinearError x lengthUnit 1), contact_erp 0.0093 at dt = 1 ms'],
      ['contact stiffness', 'not a knob: in 0.21.0 setting normalizedAllowedLinearError (1e-5) or contact_natural_frequency (300) changes no figure of car.circle, although the getters read the new values'],
      ['joints', 'revolute impulse joints (JointData.revolute): steering about the chassis z, front spin about the knuckle y (one knuckle per front wheel; four wheels at their Ackermann angles), rear wheels about the chassis y; multibody joints are not used: Rapier\'s JS multibody joints have no motors'],
      ['motors', `steering and front spin: configureMotorModel(AccelerationBased), configureMotorVelocity(rate, ${MOTOR_FACTOR_DT}/dt), setMotorMaxForce(the request's torque limit)`],
      ['bodies', 'chassis cuboid collider with setMass (collision groups 0: collides with nothing); knuckle setAdditionalMassProperties (inertia m x 2e-3 m^2); ball wheels setMass (Rapier\'s solid-ball inertia)'],
      ['friction', 'wheel and ground colliders both friction mu, restitution 0; Rapier\'s default combine rule (Average) gives mu'],
      ['contact forces', 'not read: rapier3d-compat 0.21.0\'s contact manifolds (World.contactPair, TempContactManifold) give the normal impulse (contactImpulse) but zero friction impulses (contactTangentImpulseX/Y): its default Simplified friction model\'s twist-friction constraints do not write tangent_impulse back, and the JS API sets no other friction model; contact force events carry the normal impulses only. A ground force without its friction would fail the momentum and hold checks for want of data: no ground_force_W is sent, so the load, momentum and hold checks are skipped'],
      ['ground', `cuboid ${2 * GROUND_HALF_M} m x ${2 * GROUND_HALF_M} m x 1 m, top face z = 0, centred under the start (float32: kept small)`],
      ['disks', `M ball 1 kg, linvel set before each step, translations z locked, rotations locked (RigidBodyDesc.lockRotations); N kinematicPositionBased ball, setNextKinematicTranslation(cN_next); friction 0, restitution 0; ${CONFIG.solver} solver iterations, ${CONFIG.pgs} PGS; contacts: the points of the M-N manifold the step used (predictive ones included); signed distance n . (p2 - p1) of each point's two local points at the start poses, as Rapier's solver measures it (contactDist is the distance when the narrow phase last recomputed the manifold, which it does not do every step)`],
    ],
  }),
  car: buildCar,
  disks: buildDisks,
  stepCar,
  stepDisks,
});
