// Havok (@babylonjs/havok on npm, the WASM build Babylon.js ships, single precision) served over
// liftcheck's engine protocol (docs/protocol.md), set up as its users run it: the ideal step time
// is the step it is called with. HavokPhysics.d.ts (1.3.14) documents HP_World_SetIdealStepTime as
// "the ideal delta time which you intend to call HP_World_Step() with", from which the solver
// parameters are adjusted when the step differs; Havok's samples set it to their fixed step, and
// Babylon.js's HavokPlugin.executeStep calls HP_World_SetIdealStepTime(world, deltaTime) right
// before every HP_World_Step, so its users run the two equal. Left at 1/60 s under a 1 ms step, the
// radii of car.circle were off by 356% and car.slope's car left the ground: that is a misuse, not a
// configuration (the knob ideal_step_time keeps it reachable). This build exposes no solver
// iterations; its other world setting, HP_World_SetSpeedLimit (200 m/s, 100 rad/s), is never reached.
// Car: a chassis box (collides with nothing), per front wheel (one for the tricycle, two for the
// four-wheel car) a steering knuckle on a 6-DOF constraint with only ANGULAR_X free about the
// vertical through the wheel centre, the wheel on one with only
// ANGULAR_X free about the knuckle's y (Babylon.js's HingeConstraint), both with VELOCITY motors
// limited to the servo's torques; the rear wheels on passive ones about the chassis y. Joint
// angles are read from the bodies' orientations (Havok has no joint-angle query).
// Disks: M a dynamic sphere whose linear velocity is set before each step, N a kinematic sphere
// moved with HP_Body_SetTargetQTransform; contacts from the collision events of the step
// (COLLISION_STARTED, COLLISION_CONTINUED), each with its points on M and N and the normal, so the
// signed distance is (p_B - p_A) . n_A (positive for Havok's contacts ahead of touching).
// Every build releases the previous world with all its bodies, shapes and constraints.
import { serve, timed } from './protocol.mjs';
import * as C from './common.mjs';
import { readFileSync } from 'node:fs';

const PKG = new URL('./node_modules/@babylonjs/havok/', import.meta.url);
const VERSION = JSON.parse(readFileSync(new URL('package.json', PKG))).version;
// Under Node the WASM file is not found by the module itself: it is handed in.
const HK = await (await import(new URL('lib/esm/HavokPhysics_es.js', PKG))).default({ wasmBinary: readFileSync(new URL('lib/esm/HavokPhysics.wasm', PKG)) });

// Collision filters [membership, collides with]: ground and wheels collide, ghosts (chassis,
// knuckle) collide with nothing, disks with each other.
const F_GROUND = [1, 2], F_WHEEL = [2, 1], F_GHOST = [4, 0], F_DISK = [8, 8];
const A = HK.ConstraintAxis, LOCKED = HK.ConstraintAxisLimitMode.LOCKED;
// Babylon.js's PhysicsMaterial combines friction with MINIMUM unless told otherwise; both
// materials use it, so the pair's coefficient is min(f_wheel, f_ground) (measured: a box sliding
// on the ground decelerates at min(f1, f2) g; of two materials with different modes the one
// later in GEOMETRIC_MEAN, MINIMUM, MAXIMUM, ARITHMETIC_MEAN, MULTIPLY wins).
const COMBINE = HK.MaterialCombine.MINIMUM, RESTITUTION_COMBINE = HK.MaterialCombine.MAXIMUM;

C.parseArgs(process.argv.slice(2), { default: true });
const SETTINGS = ['car', 'disks'].map((vehicle) => ({
  key: 'ideal_step_time', vehicle, kind: 'choice', choices: ['dt', '1/60', 'off'], default: 'dt',
  help: 'HP_World_SetIdealStepTime: the run\'s dt (as its users set it), 1/60 s (the value a new world has), or off (0: no adaptation of the solver to the step)',
}));
SETTINGS.splice(1, 0, C.WHEEL_KNOB);

// Why the step replies carry no ground_force_W (docs/protocol.md): the only contact report of
// @babylonjs/havok 1.3.14 is the collision event (HavokPhysics.d.ts: CollisionEvent = [type,
// contact on A, contact on B, "Impulse applied": number], one event per contact point, from
// HP_World_GetCollisionEvents / HP_World_GetNextCollisionEvent after HP_Body_SetEventMask with
// COLLISION_STARTED | COLLISION_CONTINUED). That scalar is the point's NORMAL impulse alone:
// measured, a box sliding at 2 m/s on mu = 0.5 reports impulses summing to m g dt while friction
// takes mu m g dt off its momentum, and a sphere sliding before it rolls reports m g dt to 1e-9.
// No call gives the friction impulses (the declaration's other impulse getter,
// HP_Constraint_GetAppliedImpulses, is for constraints, not contacts; Babylon.js's HavokPlugin
// passes the same scalar on as IPhysicsCollisionEvent.impulse). A ground force without its
// friction would fail the momentum and hold checks for want of data, and one rebuilt from the
// bodies' velocity change would check the momentum against itself: neither is sent.
const CONTACT_FORCES_NOT_READ = 'not read: Havok\'s collision events (HP_World_GetCollisionEvents, HP_Event_AsCollision; HavokPhysics.d.ts 1.3.14 CollisionEvent = [type, contact on A, contact on B, "Impulse applied": number]) carry one scalar per contact point, the normal impulse only (measured: on a box sliding on mu = 0.5 they sum to m g dt while friction removes mu m g dt), and no call gives the friction impulses (HP_Constraint_GetAppliedImpulses is for constraints): no ground_force_W is sent, so the load, momentum and hold checks are skipped';

let world = null;  // { id, bodies, shapes, constraints, kind, ... }

function ok(result, what) {
  const r = Array.isArray(result) ? result[0] : result;
  if (r !== HK.Result.RESULT_OK) throw new Error(`Havok: ${what} failed`);
  return Array.isArray(result) ? result[1] : undefined;
}

function dropWorld() {
  if (!world) return;
  for (const c of world.constraints) HK.HP_Constraint_Release(c);
  for (const b of world.bodies) {
    HK.HP_World_RemoveBody(world.id, b);
    HK.HP_Body_Release(b);
  }
  for (const s of world.shapes) HK.HP_Shape_Release(s);
  HK.HP_World_Release(world.id);
  world = null;
}

/// A new world with the request's gravity and the ideal step time the knob names. Havok has no
/// getter for it: the value set is kept in world.ideal_s and sent back in the build reply
/// (ideal_step_time_s), for the adapter's tests.
function newWorld(gravity_W, knob, dt_s) {
  dropWorld();
  const id = ok(HK.HP_World_Create(), 'HP_World_Create');
  ok(HK.HP_World_SetGravity(id, gravity_W), 'HP_World_SetGravity');
  const ideal_s = { '1/60': 1 / 60, dt: dt_s, off: 0 }[knob.ideal_step_time];
  ok(HK.HP_World_SetIdealStepTime(id, ideal_s), 'HP_World_SetIdealStepTime');
  world = { id, bodies: [], shapes: [], constraints: [], ideal_s, follows_dt: knob.ideal_step_time === 'dt' };
}

/// One world step of dt_s. Where the ideal step time follows the step, a step of another length
/// (a run's last, shorter one) re-sets it first: it is the step "you intend to call HP_World_Step() with".
function worldStep(dt_s) {
  if (world.follows_dt && dt_s !== world.ideal_s) {
    ok(HK.HP_World_SetIdealStepTime(world.id, dt_s), 'HP_World_SetIdealStepTime');
    world.ideal_s = dt_s;
  }
  return timed(() => HK.HP_World_Step(world.id, dt_s));
}

function shape(made, filter, friction) {
  const s = ok(made, 'shape creation');
  world.shapes.push(s);
  ok(HK.HP_Shape_SetFilterInfo(s, filter), 'HP_Shape_SetFilterInfo');
  ok(HK.HP_Shape_SetMaterial(s, [friction, friction, 0, COMBINE, RESTITUTION_COMBINE]), 'HP_Shape_SetMaterial');
  return s;
}

/// A body of shape s at pose (p_W, q_W); mass_kg > 0: dynamic, with the inertia Havok computes for
/// the shape scaled to that mass; else the given motion type.
function addBody(s, p_W, q_W, motion, mass_kg) {
  const b = ok(HK.HP_Body_Create(), 'HP_Body_Create');
  world.bodies.push(b);
  ok(HK.HP_Body_SetShape(b, s), 'HP_Body_SetShape');
  ok(HK.HP_Body_SetMotionType(b, motion), 'HP_Body_SetMotionType');
  if (mass_kg > 0) {
    const mp = ok(HK.HP_Shape_BuildMassProperties(s), 'HP_Shape_BuildMassProperties');  // inertia per unit mass
    mp[1] = mass_kg;
    ok(HK.HP_Body_SetMassProperties(b, mp), 'HP_Body_SetMassProperties');
  }
  ok(HK.HP_Body_SetQTransform(b, [p_W, q_W]), 'HP_Body_SetQTransform');
  HK.HP_Body_SetLinearDamping(b, 0);
  HK.HP_Body_SetAngularDamping(b, 0);
  ok(HK.HP_World_AddBody(world.id, b, false), 'HP_World_AddBody');
  HK.HP_Body_SetActivationControl(b, HK.ActivationControl.ALWAYS_ACTIVE);
  return b;
}

/// A hinge (6-DOF constraint, ANGULAR_X free) between parent and child: pivot and axes in each
/// body's own frame (axis_x the hinge axis, axis_y where both bodies' angle is zero);
/// motor_Nm > 0 gives it a velocity motor.
function addHinge(parent, child, pivot_P, axis_x_P, axis_y_P, pivot_C, axis_x_C, axis_y_C, motor_Nm) {
  const c = ok(HK.HP_Constraint_Create(), 'HP_Constraint_Create');
  world.constraints.push(c);
  HK.HP_Constraint_SetParentBody(c, parent);
  HK.HP_Constraint_SetChildBody(c, child);
  HK.HP_Constraint_SetAnchorInParent(c, pivot_P, axis_x_P, axis_y_P);
  HK.HP_Constraint_SetAnchorInChild(c, pivot_C, axis_x_C, axis_y_C);
  for (const axis of [A.LINEAR_X, A.LINEAR_Y, A.LINEAR_Z, A.ANGULAR_Y, A.ANGULAR_Z]) HK.HP_Constraint_SetAxisMode(c, axis, LOCKED);
  if (motor_Nm > 0) {
    HK.HP_Constraint_SetAxisMotorType(c, A.ANGULAR_X, HK.ConstraintMotorType.VELOCITY);
    HK.HP_Constraint_SetAxisMotorMaxForce(c, A.ANGULAR_X, motor_Nm);
    HK.HP_Constraint_SetAxisMotorTarget(c, A.ANGULAR_X, 0);
  }
  HK.HP_Constraint_SetCollisionsEnabled(c, 0);
  ok(HK.HP_Constraint_SetEnabled(c, 1), 'HP_Constraint_SetEnabled');
  return c;
}

function buildCar(req) {
  dropWorld();  // a build that fails leaves no world to step
  const { servo } = C.carRequest(req, ['sphere', 'cylinder']);
  const knob = C.applySettings(SETTINGS, req.settings, 'car');
  newWorld(req.gravity_W, knob, req.dt_s);
  const c = req.car, q0 = req.q0, R = c.R_m, DYN = HK.MotionType.DYNAMIC;
  const at = (bx, by, bz) => C.chassisPoint(q0, bx, by, bz);
  const q_chassis = C.yawQuat(q0.phi_rad);
  const side = 2 * C.groundHalf_m(c);
  // Havok's pair coefficient is min(mu, mu) = mu.
  addBody(shape(HK.HP_Shape_CreateBox([0, 0, 0], [0, 0, 0, 1], [side, side, 1]), F_GROUND, req.mu), [q0.x_m, q0.y_m, -0.5], [0, 0, 0, 1],
           HK.MotionType.STATIC, 0);
  const chassis = addBody(shape(HK.HP_Shape_CreateBox([0, 0, 0], [0, 0, 0, 1], [c.l_m, c.track_m, c.chassis_height_m]), F_GHOST, 0),
                           at(-0.5 * c.l_m, 0, R), q_chassis, DYN, c.chassis_mass_kg);
  const wheelShape = () => shape(C.wheelShapeOf(req, knob) === 'cylinder'
    ? HK.HP_Shape_CreateCylinder([0, -0.5 * c.wheel_width_m, 0], [0, 0.5 * c.wheel_width_m, 0], R)  // axis along local y
    : HK.HP_Shape_CreateSphere([0, 0, 0], R), F_WHEEL, req.mu);
  const Z = [0, 0, 1], Y = [0, 1, 0], X = [1, 0, 0], O = [0, 0, 0];
  // Each front wheel on its own knuckle, both yawed by the wheel's start steering angle b0. The
  // steering hinge's zero direction is the chassis x: (1, 0, 0) in the chassis frame, the same
  // direction (cos b0, -sin b0, 0) in the knuckle's.
  world.fronts = C.frontWheels(c, q0.beta_rad).map(({ y_m, beta0_rad: b0 }) => {
    const q_front = C.yawQuat(q0.phi_rad + b0), hub = at(0, y_m, R);
    const knuckle = addBody(shape(HK.HP_Shape_CreateSphere(O, C.KNUCKLE_RADIUS_M), F_GHOST, 0), hub, q_front, DYN, c.knuckle_mass_kg);
    const body = addBody(wheelShape(), hub, q_front, DYN, c.wheel_mass_kg);
    const steer = addHinge(chassis, knuckle, [0.5 * c.l_m, y_m, 0], Z, X, O, Z, [Math.cos(b0), -Math.sin(b0), 0], req.servo.steer_torque_max_Nm);
    const spin = addHinge(knuckle, body, O, Y, Z, O, Y, Z, req.servo.spin_torque_max_Nm);
    return { knuckle, body, steer, spin };
  });
  // The rear wheels on passive hinges; in a braked run (servo.rear_brake_Nm > 0, docs/protocol.md)
  // each rear hinge gets the front spin's motor: a VELOCITY motor on ANGULAR_X, target 0 (the
  // wheel's spin relative to the chassis), max force the brake's torque. HavokPhysics.d.ts
  // (@babylonjs/havok 1.3.14): HP_Constraint_SetAxisMotorType "controls how the motor applies forces
  // along the axis" (ConstraintMotorType.VELOCITY), HP_Constraint_SetAxisMotorMaxForce: "For angular
  // axes, `maxForce` is used as a max torque". Unbraked (0): no motor, the hinge as before.
  world.rear = [0.5, -0.5].map((y) => {
    const body = addBody(wheelShape(), at(-c.l_m, y * c.track_m, R), q_chassis, DYN, c.wheel_mass_kg);
    addHinge(chassis, body, [-0.5 * c.l_m, y * c.track_m, 0], Y, Z, O, Y, Z, servo.rear_brake_Nm);
    return body;
  });
  world.chassis = chassis;
  return { ...carState(0), ideal_step_time_s: world.ideal_s };
}

function pose(b) {
  const [p, q] = HK.HP_Body_GetQTransform(b)[1];
  return { p, q };
}

function bodyState(b) {
  const { p, q } = pose(b);
  return { p, q, v: HK.HP_Body_GetLinearVelocity(b)[1], w: HK.HP_Body_GetAngularVelocity(b)[1] };
}

function carState(engine_s) {
  const q_chassis = pose(world.chassis).q;
  // The joints' angles from the bodies: the knuckle's twist about the chassis z (the steering angle
  // itself: the hinge's zero is the chassis x), the wheel's about the knuckle y.
  const knuckles = world.fronts.map((f) => pose(f.knuckle).q), wheels = world.fronts.map((f) => bodyState(f.body));
  return C.carReply(engine_s, wheels.map((w, k) => C.twist(knuckles[k], w.q, 1)), knuckles.map((q) => C.twist(q_chassis, q, 2)),
    q_chassis, wheels, world.rear.map(bodyState));
}

function stepCar(req) {
  const { spin, steer } = C.carStep(req);
  world.fronts.forEach((f, k) => {
    HK.HP_Constraint_SetAxisMotorTarget(f.spin, A.ANGULAR_X, spin[k]);
    HK.HP_Constraint_SetAxisMotorTarget(f.steer, A.ANGULAR_X, steer[k]);
  });
  return carState(worldStep(req.dt_s));
}

function buildDisks(req) {
  dropWorld();
  const { mu_MN } = C.diskRequest(req);
  const knob = C.applySettings(SETTINGS, req.settings, 'disks');
  newWorld([0, 0, 0], knob, req.dt_s);
  // Friction mu_MN on both (MINIMUM combine): 0, frictionless, in every scenario.
  const ball = () => shape(HK.HP_Shape_CreateSphere([0, 0, 0], req.radius_m), F_DISK, mu_MN);
  world.M = addBody(ball(), [req.cM0[0], req.cM0[1], 0], [0, 0, 0, 1], HK.MotionType.DYNAMIC, 1);
  HK.HP_Body_SetGravityFactor(world.M, 0);
  // Its rotation held: zero inertia, which Havok (as Babylon.js's physics documents) takes as a body
  // that cannot turn.
  const mp = ok(HK.HP_Body_GetMassProperties(world.M), 'HP_Body_GetMassProperties');
  mp[2] = [0, 0, 0];
  ok(HK.HP_Body_SetMassProperties(world.M, mp), 'HP_Body_SetMassProperties');
  world.N = addBody(ball(), [req.cN0[0], req.cN0[1], 0], [0, 0, 0, 1], HK.MotionType.KINEMATIC, 0);
  HK.HP_Body_SetEventMask(world.M, HK.EventType.COLLISION_STARTED.value | HK.EventType.COLLISION_CONTINUED.value);
  return { ...diskState(), ideal_step_time_s: world.ideal_s };
}

function diskState() {
  const m = pose(world.M).p, n = pose(world.N).p, w = HK.HP_Body_GetAngularVelocity(world.M)[1];
  return { cM: [m[0], m[1]], cN: [n[0], n[1]], wM: [w[0], w[1], w[2]] };
}

/// The M-N collision events of the last step: their count and smallest signed distance.
function diskContacts() {
  const out = { count: 0, distance_min_m: Infinity };
  const m = world.M[0], n = world.N[0];
  let ev = HK.HP_World_GetCollisionEvents(world.id)[1];
  while (ev) {
    const [, on_a, on_b] = HK.HP_Event_AsCollision(ev)[1];
    const a = on_a[0][0], b = on_b[0][0];
    if ((a === m && b === n) || (a === n && b === m)) {
      const [pa, na, pb] = [on_a[3], on_a[4], on_b[3]];
      const d = (pb[0] - pa[0]) * na[0] + (pb[1] - pa[1]) * na[1] + (pb[2] - pa[2]) * na[2];
      out.count += 1;
      out.distance_min_m = Math.min(out.distance_min_m, d);
    }
    ev = HK.HP_World_GetNextCollisionEvent(Number(world.id[0]), ev);
  }
  return out;
}

function stepDisks(req) {
  HK.HP_Body_SetLinearVelocity(world.M, [req.vM_cmd[0], req.vM_cmd[1], 0]);  // in the plane: no out-of-plane velocity
  HK.HP_Body_SetTargetQTransform(world.N, [[req.cN_next[0], req.cN_next[1], 0], [0, 0, 0, 1]]);
  const engine_s = worldStep(req.dt_s);
  const c = diskContacts();
  const contacts = C.contactsReply(c);
  return { engine_s, ...diskState(), contacts };
}

serve({
  hello() {
    return {
      engine: 'Havok', version: VERSION, precision: 'float32',
      vehicles: ['car', 'disks'], four_wheels: true, brakes: true, settings: SETTINGS,
      fixed: [
        ['configuration', 'Havok as its users run it: HP_World_SetIdealStepTime(dt), re-set when a step of another length comes (HavokPhysics.d.ts 1.3.14: "the ideal delta time which you intend to call HP_World_Step() with", the solver parameters adjusted from it; Havok\'s samples set it to their fixed step, and Babylon.js\'s HavokPlugin.executeStep calls HP_World_SetIdealStepTime(world, deltaTime) before every HP_World_Step); everything else as a new world has it; no solver iterations are exposed; the speed limits (HP_World_SetSpeedLimit, 200 m/s and 100 rad/s) are never reached'],
        ['joints', '6-DOF constraints with only ANGULAR_X free (Babylon.js HingeConstraint): steering (knuckle about the chassis vertical) and front-wheel spin (about the knuckle y) with VELOCITY motors, max torque the servo torque; passive ones for the rear wheels (a braked run: VELOCITY motors at 0, max torque the brake\'s); joint angles from the bodies\' orientations'],
        ['bodies', `chassis box of the chassis mass (filter colliding with nothing); knuckle a ${C.KNUCKLE_RADIUS_M.toFixed(4)} m sphere of knuckle_mass_kg, colliding with nothing; wheels spheres of radius R (or y-axis cylinders) of wheel_mass_kg; inertias HP_Shape_BuildMassProperties gives for the shapes at those masses; no damping, always active`],
        ['ground', 'static box, top face z = 0, 60 m square (or 20 l) centred under the start (float32 contact precision degrades on large shapes)'],
        ['friction', 'each material names its combine mode; measured: GEOMETRIC_MEAN, MINIMUM, MAXIMUM, ARITHMETIC_MEAN, MULTIPLY do what they say, and of two different modes the later in that list wins. Both materials MINIMUM (Babylon.js PhysicsMaterial default), wheel and ground both mu: min(mu, mu) = mu; restitution 0'],
        ['disks', 'M a dynamic sphere 1 kg, gravity factor 0, friction 0, zero inertia (its rotation held), linear velocity set to the command (z = 0) before each step; N kinematic, HP_Body_SetTargetQTransform to its next position; contacts from the step\'s COLLISION_STARTED/CONTINUED events, distance (p_N - p_M) . n'],
        ['four wheels', 'two front wheels at +-track/2, each on its own knuckle and hinges as above, built at its Ackermann angle (or at beta when steered in parallel)'],
        ['contact forces', CONTACT_FORCES_NOT_READ],
      ],
    };
  },
  car: buildCar,
  disks: buildDisks,
  stepCar: stepCar,
  stepDisks: stepDisks,
});
