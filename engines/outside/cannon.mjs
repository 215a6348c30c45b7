// cannon-es (pure JavaScript, float64) served over liftcheck's engine protocol (docs/protocol.md).
//
// Car: the chassis box, the steering knuckle(s) and the sphere wheels are CANNON.Body objects;
// each front wheel's steering and spin are HingeConstraints with their rotational motors on
// (enableMotor, setMotorSpeed, setMotorMaxForce), the rear wheels plain HingeConstraints (in a
// braked run with their motors on at speed 0, up to the brake's torque); the
// tricycle or the four-wheel car (front wheels at their Ackermann angles). The
// ground is a CANNON.Plane. Wheel-ground friction comes from a ContactMaterial for the pair
// (the materials' own coefficients are unset, so cannon-es uses the pair's).
// Disks: M a dynamic sphere whose velocity is set to the command before each step (cannon-es has
// no linear motor), N a kinematic sphere given the velocity that lands it on its path; the
// contacts are the ContactEquations the narrow phase generated in the step.
//
//   node cannon.mjs --config default|accurate [--fault stale-pose|late-contact]
// The faults exist for liftcheck's fault suite: stale-pose reports the chassis pose of the
// previous step, late-contact the disk contacts of the previous step.
import * as CANNON from 'cannon-es';
import { createRequire } from 'node:module';

import { serve, timed } from './protocol.mjs';
import * as C from './common.mjs';

const VERSION = createRequire(import.meta.url)('cannon-es/package.json').version;
const CONFIGS = { default: 10, accurate: 100 };  // Gauss-Seidel iterations (cannon-es's default: 10)
const opts = C.parseArgs(process.argv.slice(2), CONFIGS, ['stale-pose', 'late-contact']);
const ITERATIONS = CONFIGS[opts.config];
const KNOBS = [{ key: 'iterations', vehicle: 'car', kind: 'integer', role: 'solver_iterations', min: 1, max: 10000, default: String(ITERATIONS),
  help: 'Gauss-Seidel solver iterations per step (world.solver.iterations)' }];

const vec = (a) => new CANNON.Vec3(a[0], a[1], a[2]);
const arr = (v) => [v.x, v.y, v.z];
const quat = (b) => [b.quaternion.x, b.quaternion.y, b.quaternion.z, b.quaternion.w];

/// A body with the exact inertia of the solid it stands for (cannon-es's own estimate is that of
/// the shape's world-aligned bounding box) and no damping (its default is 0.01).
function body(world, { mass, shape, inertia, p, q, group, mask, material, type }) {
  const b = new CANNON.Body({ mass, type, position: vec(p), quaternion: new CANNON.Quaternion(...q), linearDamping: 0,
    angularDamping: 0, collisionFilterGroup: group, collisionFilterMask: mask, material });
  if (shape) b.addShape(shape);
  if (inertia) {
    b.inertia.set(...inertia);
    b.invInertia.set(1 / inertia[0], 1 / inertia[1], 1 / inertia[2]);
    b.updateInertiaWorld(true);
  }
  world.addBody(b);
  return b;
}

/// A hinge about the local `axis` of both bodies, at pivotA in a and the origin of b, with its
/// motor on where a torque limit is given.
function hinge(world, a, b, pivotA, axis, motorMax_Nm) {
  const h = new CANNON.HingeConstraint(a, b, { pivotA: vec(pivotA), axisA: vec(axis), pivotB: vec([0, 0, 0]), axisB: vec(axis) });
  if (motorMax_Nm) h.enableMotor();
  h.motorMax_Nm = motorMax_Nm;
  world.addConstraint(h);
  return h;
}

// SPOOK parameters of the constraints' equations. cannon-es's Equation constructor calls
// setSpookParams(1e7, 4, 1/60) (Equation.js, 0.20.0: "note the hardcoded refresh rate"), and only
// contact and friction equations are re-set for world.dt by the narrow phase: a hinge's three
// point equations, two rotational equations and its motor equation would keep a 60 Hz SPOOK under a
// 1 ms step. They are given the constructor's stiffness and relaxation for the step they are
// solved in, as cannon-es users stepping at another rate do.
const CONSTRAINT_STIFFNESS = 1e7, CONSTRAINT_RELAXATION = 4;

/// Every equation of the world's constraints gets its SPOOK parameters for a step of dt_s.
function spookFor(world, dt_s) {
  for (const c of world.constraints)
    for (const eq of c.equations) eq.setSpookParams(CONSTRAINT_STIFFNESS, CONSTRAINT_RELAXATION, dt_s);
}

/// The SPOOK parameters [a, b, eps] of every constraint equation, for the build reply
/// (constraint_spook: the adapter's tests check them against dt).
function spookOf(world) {
  return world.constraints.flatMap((c) => c.equations.map((eq) => [eq.a, eq.b, eq.eps]));
}

/// cannon-es's GSSolver clamps an equation's impulse over the step (its lambda) between the
/// equation's minForce and maxForce: a torque limit T is the bound T dt.
function limitMotor(h, dt_s) {
  h.setMotorMaxForce(h.motorMax_Nm * dt_s);
}

const GROUND = 1, WHEEL = 2;
let car = null, disks = null;

function buildCar(req) {
  car = disks = null;  // a build that fails leaves no world to step
  const iterations = C.applySettings(KNOBS, req.settings, 'car').iterations;
  const { car: d, q0, servo, mu, dt_s, gravity_W } = C.carRequest(req);
  const world = new CANNON.World({ gravity: vec(gravity_W) });
  world.solver.iterations = iterations;
  const groundMat = new CANNON.Material('ground'), wheelMat = new CANNON.Material('wheel');
  world.addContactMaterial(new CANNON.ContactMaterial(groundMat, wheelMat, { friction: mu, restitution: 0 }));
  const ground = body(world, { mass: 0, shape: new CANNON.Plane(), p: [0, 0, 0], q: [0, 0, 0, 1], group: GROUND, mask: WHEEL, material: groundMat });

  const R = d.R_m, l = d.l_m, w = d.track_m;
  const yaw = C.yawQuat(q0.phi_rad);
  const chassis = body(world, { mass: d.chassis_mass_kg, shape: new CANNON.Box(vec([l / 2, w / 2, d.chassis_height_m / 2])),
    inertia: C.boxInertia(d.chassis_mass_kg, l / 2, w / 2, d.chassis_height_m / 2), p: C.chassisPoint(q0, -l / 2, 0, R), q: yaw, group: 0, mask: 0 });
  const k2 = d.knuckle_mass_kg * C.KNUCKLE_GYRATION_SQ_M2;
  const wheel = (p, q) => body(world, { mass: d.wheel_mass_kg, shape: new CANNON.Sphere(R), inertia: C.sphereInertia(d.wheel_mass_kg, R),
    p, q, group: WHEEL, mask: GROUND, material: wheelMat });
  // Each front wheel on its knuckle: steering hinge about the chassis z, spin hinge about the knuckle y.
  const fronts = C.frontWheels(d, q0.beta_rad).map(({ y_m, beta0_rad }) => {
    const at = C.chassisPoint(q0, 0, y_m, R), q = C.yawQuat(q0.phi_rad + beta0_rad);
    const knuckle = body(world, { mass: d.knuckle_mass_kg, inertia: [k2, k2, k2], p: at, q, group: 0, mask: 0 });
    const wheelBody = wheel(at, q);
    return { knuckle, wheel: wheelBody, steer: hinge(world, chassis, knuckle, [l / 2, y_m, 0], [0, 0, 1], servo.steer_Nm),
      spin: hinge(world, knuckle, wheelBody, [0, 0, 0], [0, 1, 0], servo.spin_Nm) };
  });
  // The brake of a braked run (servo.rear_brake_Nm > 0, docs/protocol.md): each rear hinge's own
  // rotational motor on, as the front spin's, held at speed 0 and limited to the brake's torque
  // (limitMotor, each step). cannon-es's HingeConstraint API (enableMotor, setMotorSpeed,
  // setMotorMaxForce: https://pmndrs.github.io/cannon-es/docs/classes/HingeConstraint.html) drives
  // its RotationalMotorEquation, which "tries to keep the relative angular velocity of the bodies
  // to a given value" (RotationalMotorEquation, cannon-es 0.20.0). Unbraked (0): plain hinges, the
  // motor equation disabled, as before.
  const brakes = [];
  const rears = [1, -1].map((s) => {
    const b = wheel(C.chassisPoint(q0, -l, s * w / 2, R), yaw);
    const h = hinge(world, chassis, b, [-l / 2, s * w / 2, 0], [0, 1, 0], servo.rear_brake_Nm);
    if (servo.rear_brake_Nm > 0) brakes.push(h);
    return b;
  });
  spookFor(world, dt_s);
  car = { world, dt_s, ground, chassis, fronts, rears, brakes, previous: null };
  return { ...carState(0), constraint_spook: spookOf(world) };
}

const state = (b) => ({ p: arr(b.position), q: quat(b), v: arr(b.velocity), w: arr(b.angularVelocity) });

function carState(engine_s) {
  const { chassis, fronts, rears } = car;
  const reply = C.carReply(engine_s, fronts.map((f) => C.twist(quat(f.knuckle), quat(f.wheel), 1)),
    fronts.map((f) => C.twist(quat(chassis), quat(f.knuckle), 2)), quat(chassis), fronts.map((f) => state(f.wheel)), rears.map(state));
  if (opts.fault !== 'stale-pose') return reply;
  const now = { x_m: reply.x_m, y_m: reply.y_m, phi_rad: reply.phi_rad };
  const stale = car.previous ?? now;
  car.previous = now;
  return { ...reply, ...stale };
}

function stepCar(req) {
  const { spin, steer, dt_s } = C.carStep(req);
  if (dt_s !== car.dt_s) {  // a step of another length (a run's last, shorter one)
    spookFor(car.world, dt_s);
    car.dt_s = dt_s;
  }
  // The motor equation holds (w_A - w_B) . axis at its target: B turning by +rate needs -rate.
  car.fronts.forEach((f, k) => {
    f.spin.setMotorSpeed(-spin[k]);
    f.steer.setMotorSpeed(-steer[k]);
    limitMotor(f.spin, dt_s);
    limitMotor(f.steer, dt_s);
  });
  for (const h of car.brakes) {  // a braked run's rear wheels: zero speed relative to the chassis
    h.setMotorSpeed(0);
    limitMotor(h, dt_s);
  }
  const engine_s = timed(() => car.world.step(dt_s));
  return { ...carState(engine_s), ground_force_W: groundForce(), v_chassis_W: arr(car.chassis.velocity) };
}

/// The force the ground exerted on the wheels in the step just taken, world frame, N: each
/// ground contact's normal row and its friction rows, as the solver left them. A row's Jacobian is
/// (-d, -ri x d) on bi and (d, rj x d) on bj (d the normal ni or the tangent t), and its
/// `multiplier` is the impulse it applied over the step's dt (GSSolver: lambda / h), so it pushes
/// bj by +d multiplier and bi by -d multiplier.
function groundForce() {
  const sum = [0, 0, 0];
  const add = (eq, d) => {
    if (eq.bi !== car.ground && eq.bj !== car.ground) return;
    const f = (eq.bj === car.ground ? -1 : 1) * eq.multiplier;
    sum[0] += f * d.x, sum[1] += f * d.y, sum[2] += f * d.z;
  };
  for (const eq of car.world.contacts) add(eq, eq.ni);
  for (const eq of car.world.frictionEquations) add(eq, eq.t);
  return sum;
}

function buildDisks(req) {
  car = disks = null;
  C.applySettings(KNOBS, req.settings, 'disks');
  const { radius_m, cM0, cN0, mu_MN } = C.diskRequest(req);
  // No gravity in the disks' plane; cannon-es bounds friction by mu |g| times the reduced mass
  // (Narrowphase: friction * (world.frictionGravity || world.gravity).length()), so the friction
  // between the disks (mu_MN, 0 in every scenario) takes the option cannon-es has for a world
  // without gravity, frictionGravity, at standard gravity.
  const world = new CANNON.World({ gravity: vec([0, 0, 0]), frictionGravity: vec([0, 0, -9.81]) });
  world.solver.iterations = ITERATIONS;
  world.defaultContactMaterial.friction = mu_MN;  // 0, frictionless, in every scenario; restitution 0 (cannon-es's default for it)
  const M = body(world, { mass: 1, shape: new CANNON.Sphere(radius_m), inertia: C.sphereInertia(1, radius_m), p: [...cM0, 0], q: [0, 0, 0, 1], group: 1, mask: 1 });
  M.linearFactor.set(1, 1, 0);  // M stays in the plane
  // Its rotation held (Body.fixedRotation, with no inverse inertia: the solver sees no rotational freedom).
  M.fixedRotation = true;
  M.invInertia.set(0, 0, 0);
  M.updateInertiaWorld(true);
  const N = body(world, { mass: 0, type: CANNON.Body.KINEMATIC, shape: new CANNON.Sphere(radius_m), p: [...cN0, 0], q: [0, 0, 0, 1], group: 1, mask: 1 });
  disks = { world, M, N, seen: none(), previous: none() };
  // The contacts' signed distances on the state the step starts from: preStep comes after the
  // solve and before the integration.
  world.addEventListener('preStep', () => { disks.seen = contactsOf(world, M, N); });
  car = null;
  return { cM: [M.position.x, M.position.y], cN: [N.position.x, N.position.y] };
}

function none() {
  return { count: 0, depth_max_m: 0, distance_min_m: 0 };
}

function contactsOf(world, M, N) {
  const c = none();
  let dmin = Infinity;
  for (const e of world.contacts) {
    if (!((e.bi === M && e.bj === N) || (e.bi === N && e.bj === M))) continue;
    // g = n . ((x_j + r_j) - (x_i + r_i)): negative when penetrating (ContactEquation.computeB)
    const gap = e.bj.position.vadd(e.rj).vsub(e.bi.position.vadd(e.ri));
    dmin = Math.min(dmin, e.ni.dot(gap));
    c.count += 1;
  }
  if (c.count > 0) Object.assign(c, { distance_min_m: dmin, depth_max_m: Math.max(0, -dmin) });
  return c;
}

function stepDisks(req) {
  const { vM, cN_next, dt_s } = C.diskStep(req);
  const { world, M, N } = disks;
  M.velocity.set(vM[0], vM[1], 0);
  N.velocity.set((cN_next[0] - N.position.x) / dt_s, (cN_next[1] - N.position.y) / dt_s, 0);
  disks.seen = none();
  const engine_s = timed(() => world.step(dt_s));
  let contacts = disks.seen;
  if (opts.fault === 'late-contact') [contacts, disks.previous] = [disks.previous, disks.seen];
  const w = M.angularVelocity;
  return { engine_s, cM: [M.position.x, M.position.y], cN: [N.position.x, N.position.y], wM: [w.x, w.y, w.z], contacts };
}

serve({
  hello: () => ({
    engine: 'cannon-es', version: VERSION, precision: 'float64', vehicles: ['car', 'disks'], four_wheels: true, brakes: true, settings: KNOBS,
    fixed: [
      ['stepping', 'world.step(dt) (fixed step, no interpolation); GSSolver, tolerance 1e-7 (default); SPOOK contact and friction stiffness 1e7, relaxation 3 (ContactMaterial defaults), for world.dt'],
      ['constraint SPOOK', 'every equation of the hinges (3 point, 2 rotational, the motor) setSpookParams(1e7, 4, dt), re-set when a step of another length comes: the Equation constructor\'s stiffness and relaxation, for the step taken instead of its hardcoded 1/60 s (Equation.js, cannon-es 0.20.0)'],
      ['joints', 'HingeConstraint steering (chassis z) and front spin (knuckle y) with rotational motors, one knuckle per front wheel (four wheels: each at its Ackermann angle); rear wheels HingeConstraint'],
      ['motors', 'setMotorSpeed(-rate) (the motor equation holds (w_A - w_B) . axis), setMotorMaxForce(torque limit x dt): GSSolver clamps each equation\'s impulse over the step between its minForce and maxForce'],
      ['bodies', 'chassis box (collides with nothing), knuckle (no shape, inertia m x 2e-3 m^2), sphere wheels; exact solid inertias set (cannon-es estimates a world-aligned bounding box); damping 0 (default 0.01)'],
      ['friction', 'ContactMaterial(ground, wheel) friction mu, restitution 0 (the materials have no coefficients, so the pair\'s apply); cannon-es clamps each friction row\'s impulse over the step at mu g times the pair\'s reduced mass (the wheel\'s mass), not at mu times the normal impulse: at dt = 1 ms a force of mu g m / dt, a thousand times the wheel\'s weight'],
      ['ground', 'CANNON.Plane z = 0'],
      ['contact forces', 'each ground contact\'s normal and friction rows after the step (world.contacts, world.frictionEquations): their direction times the solver\'s multiplier (the row\'s impulse over dt), summed: each step reply\'s ground_force_W, with the chassis\'s centre-of-mass velocity v_chassis_W (the load and momentum checks)'],
      ['disks', `M sphere 1 kg, velocity set before each step, linearFactor (1, 1, 0), fixedRotation with no inverse inertia; frictionGravity 9.81 m/s^2 (friction mu_MN between the disks, 0 in every scenario); N kinematic sphere, velocity that lands it on cN_next; frictionless, restitution 0; ${ITERATIONS} iterations; contacts: the step's ContactEquations (narrow phase on the start state), signed distance n . (x_j + r_j - x_i - r_i)`],
    ],
  }),
  car: buildCar,
  disks: buildDisks,
  stepCar,
  stepDisks,
});
