// Jolt Physics (jolt-physics on npm, the WASM build, single precision) served over liftcheck's
// engine protocol (docs/protocol.md). Two configurations, chosen with --config:
//   default   Jolt's PhysicsSettings as shipped: 10 velocity steps, 2 position steps, 2 cm
//             penetration slop (Jolt/Physics/PhysicsSettings.h).
//   accurate  what Jolt's author recommends where light bodies carry heavy ones: "increasing the
//             iteration count a lot (PhysicsSettings::mNumVelocitySteps, mNumPositionSteps)"
//             (jrouwe/JoltPhysics issue 151; issue 241 names the same hard case, a light body
//             between the floor and a heavy one), the cheapest setting measured to give what
//             100 velocity and 20 position steps give: 100 velocity steps, the default 2 position
//             steps (20 changed car.circle's radii by 1.5%, car.cycle's dx by 1%, at four times
//             the cost), and a 1 mm penetration slop (PhysicsSettings::mPenetrationSlop, "how much
//             bodies are allowed to sink into each other"; it costs nothing per step, and at 2 cm
//             a 37 s lap sinks the hub 20 mm, at 1 mm 1 mm).
// Car: a chassis box (collides with nothing), per front wheel (one for the tricycle, two for the
// four-wheel car) a steering knuckle on a HingeConstraint about the vertical through the wheel
// centre and the wheel on a HingeConstraint about the knuckle's y,
// both with velocity motors (EMotorState_Velocity) limited to the servo's torques; the rear wheels
// on passive HingeConstraints about the chassis y (in a braked run with the same velocity motor,
// target 0, limited to the brake's torque). Disks: M a dynamic sphere whose linear velocity
// is set before each step (Plane2D degrees of freedom), N a kinematic sphere moved with
// MoveKinematic; contacts from a ContactListener (OnContactAdded/OnContactPersisted), speculative
// manifolds included with their negative penetration depth.
// Contact forces (each car step reply's ground_force_W, with the chassis's v_chassis_W): the
// binding has no accessor for a contact's solved impulses (ContactListener sees a manifold and
// its ContactSettings before the solve; ContactConstraintManager is not exposed). The impulses are
// read where Jolt itself keeps them for warm starting: after the velocity solve
// ContactConstraintManager::StoreAppliedImpulses copies every contact constraint's total lambdas
// into the contact cache, which PhysicsSystem::SaveState(recorder, EStateRecorderState_Contacts)
// serialises; the world normal each manifold's constraint used comes from a ContactListener
// (groundListener, groundForce below). Neither changes the simulation: the poses are bit-identical
// with and without them.
// Every build makes a new JoltInterface and destroys the previous one with all its bodies and
// constraints (one process serves many runs).
import { serve, timed } from './protocol.mjs';
import * as C from './common.mjs';
import { readFileSync } from 'node:fs';

const Jolt = await (await import('jolt-physics')).default();
const VERSION = JSON.parse(readFileSync(new URL('./node_modules/jolt-physics/package.json', import.meta.url))).version;

const PRESETS = {
  default: { velocity_steps: 10, position_steps: 2, penetration_slop_m: 0.02 },
  accurate: { velocity_steps: 100, position_steps: 2, penetration_slop_m: 0.001 },
};
const CONFIG = (() => {
  const i = process.argv.indexOf('--config');
  const name = i >= 0 ? process.argv[i + 1] : 'default';
  if (!PRESETS[name]) {
    process.stderr.write(`jolt.mjs: --config '${name}' is not one of ${Object.keys(PRESETS).join(' | ')}\n`);
    process.exit(2);
  }
  return name;
})();

function knobs(vehicle) {
  const p = PRESETS[CONFIG];
  return [
    { key: 'velocity_steps', vehicle, kind: 'integer', role: 'solver_iterations', min: 2, max: 1000, default: String(p.velocity_steps),
      help: 'PhysicsSettings::mNumVelocitySteps, solver velocity iterations per step (Jolt needs >= 2 for friction)' },
    { key: 'position_steps', vehicle, kind: 'integer', role: 'solver_iterations', min: 0, max: 1000, default: String(p.position_steps),
      help: 'PhysicsSettings::mNumPositionSteps, position (drift) iterations per step' },
    { key: 'penetration_slop_m', vehicle, kind: 'real', min: 0, max: 0.1, default: String(p.penetration_slop_m),
      help: 'PhysicsSettings::mPenetrationSlop, m: how far bodies may sink into each other before the position solver pushes them out' },
  ];
}
// On the disks only the slop is a knob: M sinks 0.1 mm into N on disks.forced, below either
// preset's slop, so the position steps act only once the slop is set below that (slop 0 takes the
// penetration to 1.2e-6 m), and one velocity step solves the single frictionless contact with a
// kinematic N (no value from 2 to 1000 changes a disk record). The disks take the preset's
// velocity and position steps.
const SETTINGS = [...knobs('car'), C.WHEEL_KNOB, ...knobs('disks').filter((k) => k.key === 'penetration_slop_m')];

// Object layers: the ground, wheels (collide with the ground only), ghosts (chassis and knuckle,
// collide with nothing), disks (collide with each other).
const L_GROUND = 0, L_WHEEL = 1, L_GHOST = 2, L_DISK = 3, N_LAYERS = 4;

let world = null;  // { jolt, system, bodies: Body[], constraints: Constraint[], listener, kind, ... }

function vec3(v) { return new Jolt.Vec3(v[0], v[1], v[2]); }
function rvec3(v) { return new Jolt.RVec3(v[0], v[1], v[2]); }
function quat(q) { return new Jolt.Quat(q[0], q[1], q[2], q[3]); }
function destroyAll(...objs) { for (const o of objs) Jolt.destroy(o); }

/// A JoltInterface with the four layers and the knob values applied.
function makeSystem(knob, gravity_W) {
  const settings = new Jolt.JoltSettings();
  const pairs = new Jolt.ObjectLayerPairFilterTable(N_LAYERS);
  pairs.EnableCollision(L_GROUND, L_WHEEL);
  pairs.EnableCollision(L_DISK, L_DISK);
  const bp_static = new Jolt.BroadPhaseLayer(0), bp_moving = new Jolt.BroadPhaseLayer(1);
  const bp = new Jolt.BroadPhaseLayerInterfaceTable(N_LAYERS, 2);
  bp.MapObjectToBroadPhaseLayer(L_GROUND, bp_static);
  for (const l of [L_WHEEL, L_GHOST, L_DISK]) bp.MapObjectToBroadPhaseLayer(l, bp_moving);
  settings.mObjectLayerPairFilter = pairs;
  settings.mBroadPhaseLayerInterface = bp;
  settings.mObjectVsBroadPhaseLayerFilter = new Jolt.ObjectVsBroadPhaseLayerFilterTable(bp, 2, pairs, N_LAYERS);
  const jolt = new Jolt.JoltInterface(settings);  // owns the filters from here on
  destroyAll(settings, bp_static, bp_moving);
  const system = jolt.GetPhysicsSystem();
  const ps = new Jolt.PhysicsSettings();  // Jolt's defaults, then the knobs
  ps.mNumVelocitySteps = knob.velocity_steps;
  ps.mNumPositionSteps = knob.position_steps;
  ps.mPenetrationSlop = knob.penetration_slop_m;
  system.SetPhysicsSettings(ps);
  Jolt.destroy(ps);
  const g = vec3(gravity_W);
  system.SetGravity(g);
  Jolt.destroy(g);
  return { jolt, system, bi: system.GetBodyInterface(), bodies: [], constraints: [], listener: null, owned: [] };
}

function dropWorld() {
  if (!world) return;
  const { jolt, system, bi } = world;
  for (const c of world.constraints) system.RemoveConstraint(c);
  for (const b of world.bodies) {
    const id = b.GetID();
    bi.RemoveBody(id);
    bi.DestroyBody(id);
  }
  if (world.listener) {
    system.SetContactListener(null);
    Jolt.destroy(world.listener);
  }
  for (const o of world.owned) Jolt.destroy(o);
  Jolt.destroy(jolt);
  world = null;
}

/// Adds a body: shape (owned by the body from here on), pose, motion type and layer; mass_kg
/// sets the mass with the inertia Jolt computes from the shape for it.
function addBody(shape, p_W, q_W, motion, layer, opts = {}) {
  const pos = rvec3(p_W), rot = quat(q_W);
  const s = new Jolt.BodyCreationSettings(shape, pos, rot, motion, layer);
  destroyAll(pos, rot);
  s.mAllowSleeping = false;
  s.mLinearDamping = 0;
  s.mAngularDamping = 0;
  s.mFriction = opts.friction ?? 0;
  s.mRestitution = 0;
  if (opts.gravity_factor !== undefined) s.mGravityFactor = opts.gravity_factor;
  if (opts.dofs !== undefined) s.mAllowedDOFs = opts.dofs;
  if (opts.mass_kg !== undefined) {
    s.mOverrideMassProperties = Jolt.EOverrideMassProperties_CalculateInertia;
    s.mMassPropertiesOverride.mMass = opts.mass_kg;
  }
  const body = world.bi.CreateBody(s);
  Jolt.destroy(s);
  world.bi.AddBody(body.GetID(), Jolt.EActivation_Activate);
  world.bodies.push(body);
  return body;
}

/// A hinge between body1 and body2 about the world axis through p_W (normal: a world direction
/// perpendicular to it, where both bodies' angle is zero); motor_Nm > 0 gives it a velocity motor.
function addHinge(body1, body2, p_W, axis_W, normal_W, motor_Nm) {
  const s = new Jolt.HingeConstraintSettings();
  s.mSpace = Jolt.EConstraintSpace_WorldSpace;
  const p1 = rvec3(p_W), p2 = rvec3(p_W), a1 = vec3(axis_W), a2 = vec3(axis_W), n1 = vec3(normal_W), n2 = vec3(normal_W);
  s.mPoint1 = p1; s.mPoint2 = p2; s.mHingeAxis1 = a1; s.mHingeAxis2 = a2; s.mNormalAxis1 = n1; s.mNormalAxis2 = n2;
  if (motor_Nm > 0) {
    s.mMotorSettings.mMinTorqueLimit = -motor_Nm;
    s.mMotorSettings.mMaxTorqueLimit = motor_Nm;
  }
  const c = s.Create(body1, body2);
  destroyAll(s, p1, p2, a1, a2, n1, n2);
  world.system.AddConstraint(c);
  world.constraints.push(c);
  const hinge = Jolt.castObject(c, Jolt.HingeConstraint);
  if (motor_Nm > 0) hinge.SetMotorState(Jolt.EMotorState_Velocity);
  return hinge;
}

function buildCar(req) {
  dropWorld();  // a build that fails leaves no world to step
  const { servo } = C.carRequest(req, ['sphere', 'cylinder']);
  const knob = C.applySettings(SETTINGS, req.settings, 'car');
  world = makeSystem(knob, req.gravity_W);
  const c = req.car, q0 = req.q0, R = c.R_m;
  const at = (bx, by, bz) => C.chassisPoint(q0, bx, by, bz);
  const q_chassis = C.yawQuat(q0.phi_rad);
  const half = C.groundHalf_m(c);
  const ext = vec3([half, half, 0.5]);
  world.ground = addBody(new Jolt.BoxShape(ext, 0.05, null), [q0.x_m, q0.y_m, -0.5], [0, 0, 0, 1], Jolt.EMotionType_Static, L_GROUND,
           { friction: req.mu });  // Jolt combines friction as sqrt(f_wheel f_ground): both mu give mu
  Jolt.destroy(ext);
  const box = vec3([0.5 * c.l_m, 0.5 * c.track_m, 0.5 * c.chassis_height_m]);
  const chassis = addBody(new Jolt.BoxShape(box, 0, null), at(-0.5 * c.l_m, 0, R), q_chassis, Jolt.EMotionType_Dynamic, L_GHOST,
                           { mass_kg: c.chassis_mass_kg });
  Jolt.destroy(box);
  const wheelShape = () => C.wheelShapeOf(req, knob) === 'cylinder'
    ? new Jolt.CylinderShape(0.5 * c.wheel_width_m, R, Math.min(0.05, 0.25 * c.wheel_width_m), null)  // axis along local y
    : new Jolt.SphereShape(R, null);
  const wheel = (p, q) => addBody(wheelShape(), p, q, Jolt.EMotionType_Dynamic, L_WHEEL, { mass_kg: c.wheel_mass_kg, friction: req.mu });
  // Each front wheel on its own knuckle, both yawed by the wheel's start steering angle.
  world.fronts = C.frontWheels(c, q0.beta_rad).map(({ y_m, beta0_rad }) => {
    const q_front = C.yawQuat(q0.phi_rad + beta0_rad), hub = at(0, y_m, R);
    const knuckle = addBody(new Jolt.SphereShape(C.KNUCKLE_RADIUS_M, null), hub, q_front, Jolt.EMotionType_Dynamic, L_GHOST,
                             { mass_kg: c.knuckle_mass_kg });
    const body = wheel(hub, q_front);
    const steer = addHinge(chassis, knuckle, hub, [0, 0, 1], C.rotate(q_front, [1, 0, 0]), req.servo.steer_torque_max_Nm);
    const spin = addHinge(knuckle, body, hub, C.rotate(q_front, [0, 1, 0]), [0, 0, 1], req.servo.spin_torque_max_Nm);
    return { body, steer, spin, beta0_rad };
  });
  const axle_chassis = C.rotate(q_chassis, [0, 1, 0]);
  // The brake of a braked run (servo.rear_brake_Nm > 0, docs/protocol.md): each rear hinge gets
  // the same motor as the front spin's (addHinge: MotorSettings mMinTorqueLimit / mMaxTorqueLimit
  // = -+ the brake's torque, SetMotorState(EMotorState_Velocity)), its target angular velocity 0
  // relative to the chassis (SetTargetAngularVelocity, each step as the front spin's). Jolt's
  // documentation: HingeConstraint::SetMotorState / SetTargetAngularVelocity,
  // https://jrouwe.github.io/JoltPhysics/class_hinge_constraint.html, and EMotorState::Velocity,
  // "Motor will drive to target velocity limited only by max force/torque that the motor can
  // apply" (Jolt/Physics/Constraints/MotorSettings.h,
  // https://jrouwe.github.io/JoltPhysics/class_motor_settings.html). Unbraked (0): passive hinges
  // as before, no motor.
  world.brakes = [];
  world.rear = [0.5, -0.5].map((y) => {
    const body = wheel(at(-c.l_m, y * c.track_m, R), q_chassis);
    const hinge = addHinge(chassis, body, at(-c.l_m, y * c.track_m, R), axle_chassis, [0, 0, 1], servo.rear_brake_Nm);
    if (servo.rear_brake_Nm > 0) {
      hinge.SetTargetAngularVelocity(0);
      world.brakes.push(hinge);
    }
    return body;
  });
  world.chassis = chassis;
  world.normals = new Map();
  world.listener = groundListener();
  world.system.SetContactListener(world.listener);
  return carState(0);
}

function pose(body) {
  const p = body.GetPosition(), q = body.GetRotation();
  return { p: [p.GetX(), p.GetY(), p.GetZ()], q: [q.GetX(), q.GetY(), q.GetZ(), q.GetW()] };
}

/// A wheel's body state {p, q, v, w}, copied out of the binding's reused result objects.
function bodyState(body) {
  const { p, q } = pose(body);
  const v = body.GetLinearVelocity(), v_W = [v.GetX(), v.GetY(), v.GetZ()];
  const w = body.GetAngularVelocity(), w_W = [w.GetX(), w.GetY(), w.GetZ()];
  return { p, q, v: v_W, w: w_W };
}

function carState(engine_s) {
  // Hinge angles are zero at the build pose: the steering angle is the start angle plus it.
  return C.carReply(engine_s, world.fronts.map((f) => f.spin.GetCurrentAngle()), world.fronts.map((f) => f.beta0_rad + f.steer.GetCurrentAngle()),
    pose(world.chassis).q, world.fronts.map((f) => bodyState(f.body)), world.rear.map(bodyState));
}

function stepCar(req) {
  const { spin, steer } = C.carStep(req);
  world.fronts.forEach((f, k) => {
    f.spin.SetTargetAngularVelocity(spin[k]);
    f.steer.SetTargetAngularVelocity(steer[k]);
  });
  for (const b of world.brakes) b.SetTargetAngularVelocity(0);  // braked: rear wheels at zero rate against the chassis
  world.normals.clear();  // filled by groundListener during the step
  world.listener_s = 0;
  // One collision step: the contact cache then holds the whole step's impulses (with more, only
  // the last sub-step's, which groundForce would divide by the whole dt).
  // engine_s: the step less the listener's own JavaScript (Jolt's calling it stays counted).
  const engine_s = Math.max(0, timed(() => world.jolt.Step(req.dt_s, 1)) - world.listener_s);
  // Body::GetLinearVelocity: the centre of mass's, world frame (copied out at once: carState's
  // calls reuse the binding's result object)
  const v = world.chassis.GetLinearVelocity(), v_chassis_W = [v.GetX(), v.GetY(), v.GetZ()];
  return { ...carState(engine_s), ground_force_W: groundForce(req.dt_s), v_chassis_W };
}

/// The key of a manifold in Jolt's contact cache, SubShapeIDPair (body 1's id, its sub-shape id,
/// body 2's, its sub-shape id), as a string.
const manifoldKey = (id1, s1, id2, s2) => `${id1}:${s1}:${id2}:${s2}`;

/// Keeps the world-space normal of every manifold the step's contact constraints are built from
/// (world.normals, by manifold key). ContactConstraintManager calls OnContactAdded /
/// OnContactPersisted with the bodies in its own order (body 1 the lower id) and the very normal
/// the constraint takes (AddContactConstraint: inManifold.mWorldSpaceNormal; GetContactsFromCache:
/// the cached normal turned to the world, world_space_normal, for the callback and the constraint
/// alike). The cache keeps that normal only in body 2's space at the step's start, and the friction
/// axes follow from the world normal through a branch on |n_x| > |n_y| (GetTangents), which a
/// normal rebuilt from the cache can take the other way when n is nearly vertical: so the normal
/// is taken from here. The listener changes nothing: OnContactValidate answers what Jolt's
/// ContactListener does by default (AcceptAllContactsForThisBodyPair), and the settings are left
/// as they come.
function groundListener() {
  const listener = new Jolt.ContactListenerJS();
  const idOf = new Map(world.bodies.map((b) => [Jolt.getPointer(b), b.GetID().GetIndexAndSequenceNumber()]));
  const seen = (b1, b2, manifold_ptr) => {
    const t0 = process.hrtime.bigint();
    try { keep(b1, b2, manifold_ptr); } finally { world.listener_s += Number(process.hrtime.bigint() - t0) * 1e-9; }
  };
  const keep = (b1, b2, manifold_ptr) => {
    const m = Jolt.wrapPointer(manifold_ptr, Jolt.ContactManifold), n = m.mWorldSpaceNormal;
    world.normals.set(manifoldKey(idOf.get(b1), m.mSubShapeID1.GetValue() >>> 0, idOf.get(b2), m.mSubShapeID2.GetValue() >>> 0),
                      [n.GetX(), n.GetY(), n.GetZ()]);
  };
  listener.OnContactValidate = () => Jolt.ValidateResult_AcceptAllContactsForThisBodyPair;
  listener.OnContactAdded = (b1, b2, manifold) => seen(b1, b2, manifold);
  listener.OnContactPersisted = (b1, b2, manifold) => seen(b1, b2, manifold);
  listener.OnContactRemoved = () => {};
  return listener;
}

/// A StateRecorderJS that keeps the bytes written, in one growing buffer, and each WriteBytes
/// call's size: StateRecorder::Write writes every value with one WriteBytes of its size
/// (Jolt/Core/StreamOut.h), so the calls are the cache's fields one by one and their sizes check
/// the layout groundForce reads.
let recorder = null;
function contactRecorder() {
  const rec = new Jolt.StateRecorderJS();
  rec.bytes = new Uint8Array(4096);
  rec.view = new DataView(rec.bytes.buffer);
  rec.sizes = [];
  rec.end = 0;
  rec.WriteBytes = (data, size) => {
    if (rec.end + size > rec.bytes.length) {
      const grown = new Uint8Array(2 * (rec.end + size));
      grown.set(rec.bytes.subarray(0, rec.end));
      rec.bytes = grown;
      rec.view = new DataView(grown.buffer);
    }
    rec.bytes.set(Jolt.HEAPU8.subarray(data, data + size), rec.end);
    rec.end += size;
    rec.sizes.push(size);
  };
  rec.ReadBytes = () => { throw new Error('jolt.mjs: the contact recorder is only written'); };
  rec.IsEOF = () => true;
  rec.IsFailed = () => false;
  return rec;
}

/// Jolt's tangents of a contact normal n (ContactConstraintBase::GetTangents): t1 =
/// n.GetNormalizedPerpendicular(), (z, 0, -x) where x^2 > y^2 and (0, z, -y) otherwise, normalised,
/// the squares compared in float32 as Vec3::GetNormalizedPerpendicular does; t2 = n x t1.
function tangents([x, y, z]) {
  const f = Math.fround, xx = f(x * x), yy = f(y * y), zz = f(z * z);
  const len = Math.sqrt(Math.max(xx, yy) + zz);
  const t1 = xx > yy ? [z / len, 0, -x / len] : [0, z / len, -y / len];
  return [t1, [y * t1[2] - z * t1[1], z * t1[0] - x * t1[2], x * t1[1] - y * t1[0]]];
}

/// The force the ground exerted on the wheels in the step just taken, world frame, N: the solver's
/// own impulses, summed over every wheel-ground contact, over dt. Jolt keeps them in its contact
/// cache: after the velocity steps ContactConstraintManager::StoreAppliedImpulses stores each
/// contact point's non-penetration lambda (CachedContactPoint::mNonPenetrationLambda) and the
/// manifold's two friction lambdas (CachedManifold::mFrictionLambda; the friction model of Jolt
/// 5.6 applies them once per manifold, at the average contact point, plus an angular friction
/// lambda about the normal, mAngularFrictionLambda, a pure torque that adds no force), "Total
/// applied impulse during the last update", the warm start included (ContactConstraintPart::
/// WarmStart scales the total lambda and applies it; each iteration adds to it); the position
/// steps move bodies without impulses. PhysicsSystem::SaveState with EStateRecorderState_Contacts
/// writes the cache just filled (ContactConstraintManager::SaveState: mCache[mCacheWriteIdx ^ 1])
/// as (ContactConstraintManager.cpp, ManifoldCache::SaveState): the state (uint8), the number of
/// body pairs (uint32), per pair its BodyPair key (two uint32 body ids), the CachedBodyPair's
/// mDeltaPosition and mDeltaRotation (Float3 each), the number of manifolds (uint32), per manifold
/// its SubShapeIDPair key (four uint32), mNumContactPoints (uint16), mContactNormal (Float3, body
/// 2's space), mFrictionLambda (2 floats), mAngularFrictionLambda (float), and per point mPosition1,
/// mPosition2 (Float3) and mNonPenetrationLambda (float); then the CCD manifolds' keys, not read.
/// The normal n is the manifold's world normal (groundListener), "the direction along which to move
/// body 2 out of collision" (ContactManifold::mWorldSpaceNormal), and a constraint part with axis
/// d and total lambda L pushes body 2 by +L d and body 1 by -L d (ContactConstraintPart::
/// ApplyVelocityStep). Body 1 is the lower id (ContactConstraintManager::AddContactConstraint
/// swaps the pair so): here the ground, built first, so a wheel takes +(sum L_n n + L_1 t1 +
/// L_2 t2) (the other way round it would take minus that).
function groundForce(dt_s) {
  const rec = recorder ??= contactRecorder();  // one for the process, emptied each step
  rec.sizes.length = 0;
  rec.end = 0;
  world.system.SaveState(rec, Jolt.EStateRecorderState_Contacts);
  let i = 0, at = 0;
  const take = (size) => {  // the next field's offset, its size checked
    if (rec.sizes[i] !== size) throw new Error(`jolt.mjs: contact cache field ${i} has ${rec.sizes[i]} bytes, ${size} expected (not the layout of Jolt 5.6's ManifoldCache::SaveState)`);
    i++;
    at += size;
    return at - size;
  };
  const v = rec.view, u32 = (o, k = 0) => v.getUint32(o + 4 * k, true), f32 = (o, k = 0) => v.getFloat32(o + 4 * k, true);
  take(1);
  const ground = world.ground.GetID().GetIndexAndSequenceNumber();
  const force = [0, 0, 0];
  for (let pairs = u32(take(4)); pairs > 0; --pairs) {
    const pair = take(8), id1 = u32(pair, 0), id2 = u32(pair, 1);
    take(12); take(12);
    const sign = id1 === ground ? 1 : id2 === ground ? -1 : 0;  // on the wheel: body 2's impulse, or body 1's
    for (let manifolds = u32(take(4)); manifolds > 0; --manifolds) {
      const key = take(16), points = v.getUint16(take(2), true);
      take(12);
      const lf = take(8), l1 = f32(lf, 0), l2 = f32(lf, 1);
      take(4);
      let ln = 0;
      for (let k = 0; k < points; ++k) {
        take(12); take(12);
        ln += f32(take(4));
      }
      if (sign === 0 || (ln === 0 && l1 === 0 && l2 === 0)) continue;
      const n = world.normals.get(manifoldKey(u32(key, 0), u32(key, 1), u32(key, 2), u32(key, 3)));
      if (!n) throw new Error('jolt.mjs: a ground contact with impulses that no contact callback reported');
      const [t1, t2] = tangents(n);
      for (let a = 0; a < 3; ++a) force[a] += sign * (ln * n[a] + l1 * t1[a] + l2 * t2[a]) / dt_s;
    }
  }
  return force;
}

/// Counts the M-N contact points of one narrow-phase manifold and keeps the smallest signed
/// distance (Jolt's mPenetrationDepth is negative for a speculative manifold).
function contactListener() {
  const listener = new Jolt.ContactListenerJS();
  const seen = (b1, b2, manifold_ptr) => {
    const pair = [Jolt.getPointer(world.M), Jolt.getPointer(world.N)];
    if (!((b1 === pair[0] && b2 === pair[1]) || (b1 === pair[1] && b2 === pair[0]))) return;
    const m = Jolt.wrapPointer(manifold_ptr, Jolt.ContactManifold);
    world.contacts.count += m.mRelativeContactPointsOn1.size();
    world.contacts.distance_min_m = Math.min(world.contacts.distance_min_m, -m.mPenetrationDepth);
  };
  listener.OnContactValidate = () => Jolt.ValidateResult_AcceptAllContactsForThisBodyPair;
  listener.OnContactAdded = (b1, b2, manifold) => seen(b1, b2, manifold);
  listener.OnContactPersisted = (b1, b2, manifold) => seen(b1, b2, manifold);
  listener.OnContactRemoved = () => {};
  return listener;
}

function buildDisks(req) {
  dropWorld();
  const { mu_MN } = C.diskRequest(req);
  const knob = { ...PRESETS[CONFIG], ...C.applySettings(SETTINGS, req.settings, 'disks') };
  world = makeSystem(knob, [0, 0, 0]);
  world.M = addBody(new Jolt.SphereShape(req.radius_m, null), [req.cM0[0], req.cM0[1], 0], [0, 0, 0, 1], Jolt.EMotionType_Dynamic, L_DISK,
                     { mass_kg: 1, gravity_factor: 0, friction: mu_MN, dofs: Jolt.EAllowedDOFs_TranslationX | Jolt.EAllowedDOFs_TranslationY });
  // Friction mu_MN on both (Jolt's geometric mean): 0, frictionless, in every scenario.
  world.N = addBody(new Jolt.SphereShape(req.radius_m, null), [req.cN0[0], req.cN0[1], 0], [0, 0, 0, 1], Jolt.EMotionType_Kinematic, L_DISK,
                     { friction: mu_MN });
  world.listener = contactListener();
  world.system.SetContactListener(world.listener);
  world.identity = new Jolt.Quat(0, 0, 0, 1);
  world.owned.push(world.identity);
  return diskState();
}

// A by-value result of the binding is one object reused by every call of that method: copy it out
// before the next call.
function xy(body) {
  const p = body.GetPosition();
  return [p.GetX(), p.GetY()];
}

function diskState() {
  const w = world.M.GetAngularVelocity();
  return { cM: xy(world.M), cN: xy(world.N), wM: [w.GetX(), w.GetY(), w.GetZ()] };
}

function stepDisks(req) {
  const v = vec3([req.vM_cmd[0], req.vM_cmd[1], 0]);
  world.bi.SetLinearVelocity(world.M.GetID(), v);
  Jolt.destroy(v);
  const target = rvec3([req.cN_next[0], req.cN_next[1], 0]);
  world.bi.MoveKinematic(world.N.GetID(), target, world.identity, req.dt_s);
  Jolt.destroy(target);
  world.contacts = { count: 0, distance_min_m: Infinity };
  const engine_s = timed(() => world.jolt.Step(req.dt_s, 1));
  const c = world.contacts;
  const contacts = C.contactsReply(c);
  return { engine_s, ...diskState(), contacts };
}

const FIXED = {
  default: 'Jolt as shipped: PhysicsSettings defaults (10 velocity steps, 2 position steps, 2 cm penetration slop, 2 cm speculative contact distance, Baumgarte 0.2), one collision step per step',
  accurate: 'the velocity steps raised as Jolt\'s author recommends for light bodies carrying heavy ones (issue 151; issue 241 names the same case: PhysicsSettings::mNumVelocitySteps 100; mNumPositionSteps the default 2: 20 gave the same figures at four times the cost, car.circle radii 3.53e-4 / 4.52e-4 against 3.58e-4 / 4.57e-4, car.cycle 414 against 131 to 148 ms per simulated second) and mPenetrationSlop 1 mm (no cost per step; at 2 cm a 37 s lap sinks the hub 20 mm); everything else as shipped',
};

serve({
  hello() {
    return {
      engine: 'Jolt Physics', version: VERSION, precision: 'float32',
      vehicles: ['car', 'disks'], four_wheels: true, brakes: true, settings: SETTINGS,
      fixed: [
        ['configuration', FIXED[CONFIG]],
        ['joints', 'HingeConstraint steering (knuckle about the chassis vertical) and front-wheel spin (about the knuckle y), both EMotorState_Velocity with torque limits +-servo torque; passive HingeConstraints for the rear wheels (a braked run: EMotorState_Velocity at 0, torque limits +-the brake\'s)'],
        ['bodies', `chassis box of the chassis mass (layer colliding with nothing); knuckle a ${C.KNUCKLE_RADIUS_M.toFixed(4)} m sphere of knuckle_mass_kg (inertia 0.4 m r^2: 1e-4 kg m^2 at 0.05 kg), colliding with nothing; wheels spheres of radius R (or Y-axis cylinders) of wheel_mass_kg; inertias Jolt computes for the shapes at those masses; no damping, no sleeping`],
        ['ground', 'static BoxShape, top face z = 0, 60 m square (or 20 l) centred under the start'],
        ['friction', 'Jolt combines friction as the geometric mean sqrt(f1 f2): wheel and ground both mu'],
        ['disks', 'M a dynamic sphere 1 kg, gravity factor 0, friction 0, EAllowedDOFs TranslationX | TranslationY (in the plane, its rotation held), linear velocity set to the command before each step; N kinematic, MoveKinematic to its next position; contacts from ContactListener OnContactAdded/OnContactPersisted (speculative manifolds within 2 cm included, distance = -mPenetrationDepth)'],
        ['contact forces', 'the solver\'s own total lambdas of every wheel-ground contact after the step, as Jolt keeps them for warm starting (ContactConstraintManager::StoreAppliedImpulses into the contact cache), read through PhysicsSystem::SaveState(EStateRecorderState_Contacts) into a StateRecorderJS: per point the non-penetration lambda along the manifold\'s world normal (as the constraint used it, from ContactListener OnContactAdded/OnContactPersisted), per manifold the two friction lambdas along Jolt\'s tangents (ContactConstraintBase::GetTangents; the angular friction lambda is a torque), on the wheel as body 2 of the pair (the ground has the lower id), over dt: each step reply\'s ground_force_W, with the chassis\'s centre-of-mass velocity v_chassis_W (the load and momentum checks)'],
        ['four wheels', 'two front wheels at +-track/2, each on its own knuckle and hinges as above, built at its Ackermann angle (or at beta when steered in parallel)'],
      ],
    };
  },
  car: buildCar,
  disks: buildDisks,
  stepCar: stepCar,
  stepDisks: stepDisks,
});
