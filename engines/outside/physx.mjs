// NVIDIA PhysX 5 (physx-js-webidl on npm: PhysX 5.6.1 compiled to WASM, single precision) served
// over liftcheck's engine protocol (docs/protocol.md). Three configurations, chosen with --config:
//   default       the car from rigid bodies and joints (maximal coordinates): PxRigidDynamic
//                 bodies, PxRevoluteJoint with velocity drives whose limit is a torque
//                 (PxConstraintFlag::eDRIVE_LIMITS_ARE_FORCES); PGS as shipped, PhysX's default
//                 solver iteration counts (4 position, 1 velocity: PxRigidDynamic::setSolverIterationCounts).
//   tgs           the same car with the TGS solver (PxSolverType::eTGS, which "can lead to improved
//                 convergence and handle large mass ratios, long chains and jointed systems better"),
//                 with the position iterations raised as PhysX's documentation and its maintainers
//                 advise for jointed bodies (docs/adapters-physx.md).
//   articulation  the car as one PxArticulationReducedCoordinate (the chassis its floating root,
//                 knuckles and wheels links on revolute joints with velocity drives), TGS, the
//                 articulation iteration counts of Isaac Sim (PhysxSchema's PhysxArticulationAPI).
// Car contact forces (every configuration): each car step reports ground_force_W, the force the
// ground exerted on the wheels during the step, from PhysX's own solver impulses in its contact
// reports (PxSimulationEventCallback::onContact, eNOTIFY_TOUCH_FOUND | eNOTIFY_TOUCH_PERSISTS |
// eNOTIFY_CONTACT_POINTS on the wheel-ground pairs): the normal part from
// PxContactPair::extractContacts (PxContactPairPoint::impulse = normal * the applied normal
// impulse: it carries no friction), the friction part from the pair's friction anchors
// (PxContactPair::frictionPatches, PxFrictionPatch::anchorImpulses: "the impulse applied at the
// friction anchor, in world space", what PxContactPair::extractFrictionAnchors returns; PhysX
// 5.4.0: "Rigid bodies contact reporting now has friction impulse information"), both over dt.
// extractFrictionAnchors is an inline header function the WASM bindings do not export and
// PxContactPair's frictionPatches/contactPatches fields are not bound either, so the adapter reads
// the pair's struct and the PxFrictionPatch records from the WASM memory with their PhysX 5.6
// layouts (wasm32: pointers 4 bytes; PxContactPair: shapes[2] 0, contactPatches 8, contactPoints
// 12, contactImpulses 16, frictionPatches 20, requiredBufferSize 24, contactCount 28, patchCount
// 29; PxFrictionPatch, 52 bytes: anchorPositions[2] 0, anchorImpulses[2] 24, anchorCount 48),
// checked on every pair against the bound fields (contactCount, patchCount, shapes).
// Disks (every configuration): M a dynamic sphere, its rotations and z translation locked
// (PxRigidDynamicLockFlag), its linear velocity set before each step; N kinematic, moved with
// setKinematicTarget; the contacts are those PhysX reports for the pair in the step
// (PxSimulationEventCallback::onContact with eNOTIFY_CONTACT_POINTS; speculative points within the
// contact offset included, signed distance = the point's separation).
//
// The package is built for the web (emscripten ENVIRONMENT web,worker): its start-up check throws
// under Node. It starts as a worker would: globalThis.process hidden and a WorkerGlobalScope defined
// during the factory's synchronous start, the .wasm file's bytes passed in as wasmBinary.
// Every PxVec3, PxTransform, PxQuat, descriptor and filter-data object the adapter makes is
// PX.destroy'ed; every actor, joint, articulation, material and scene a build makes is released
// when the next build drops the world.
import { readFileSync } from 'node:fs';
import { serve, timed } from './protocol.mjs';
import * as C from './common.mjs';

console.log = console.error;  // the WASM loader's notices must not reach standard output

const PKG = new URL('./node_modules/physx-js-webidl/', import.meta.url);
const VERSION = JSON.parse(readFileSync(new URL('package.json', PKG))).version;

async function loadPhysX() {
  const factory = (await import(new URL('physx-js-webidl.mjs', PKG).href)).default;
  const wasmBinary = readFileSync(new URL('physx-js-webidl.wasm', PKG));
  const proc = Object.getOwnPropertyDescriptor(globalThis, 'process');
  Object.defineProperty(globalThis, 'process', { value: undefined, configurable: true, writable: true });
  globalThis.WorkerGlobalScope = function WorkerGlobalScope() {};
  let started;
  try {
    started = factory({ wasmBinary, print: (s) => process.stderr.write(`${s}\n`), printErr: (s) => process.stderr.write(`${s}\n`) });
  } finally {
    Object.defineProperty(globalThis, 'process', proc);
    delete globalThis.WorkerGlobalScope;
  }
  return started;
}
const PX = await loadPhysX();
const PV = PX.PHYSICS_VERSION;
const PHYSX_VERSION = `${(PV >> 24) & 0xff}.${(PV >> 16) & 0xff}.${(PV >> 8) & 0xff}`;

const PRESETS = {
  default: { solver: 'PGS', articulation: false, position_iterations: 4, velocity_iterations: 1 },
  tgs: { solver: 'TGS', articulation: false, position_iterations: 16, velocity_iterations: 1 },
  articulation: { solver: 'TGS', articulation: true, position_iterations: 32, velocity_iterations: 1 },
};
const opts = C.parseArgs(process.argv.slice(2), PRESETS);
const CONFIG = opts.config;
const PRESET = PRESETS[CONFIG];

// A velocity drive of the articulation: force = damping (target rate - joint rate), implicit in
// the solver, clamped at the servo's torque; the damping holds the rate to 1e-3 rad/s at the
// default car's 105.9 N m limit (Isaac Sim's velocity-driven wheels use stiffness 0 and a large
// damping the same way).
const ARTICULATION_DRIVE_DAMPING = 1e5;
// PhysX bodies default to angular damping 0.05 and a maximal angular velocity of 100 rad/s
// (PxRigidDynamic; articulation links the same): a wheel is given none of the first and a cap it
// never reaches (wheel users raise it; PhysX's vehicle snippets use free-spinning wheels).
const MAX_ANGULAR_VELOCITY = 1e4;

const KNOBS = [
  { key: 'position_iterations', vehicle: 'car', kind: 'integer', role: 'solver_iterations', min: 1, max: 255, default: String(PRESET.position_iterations),
    help: PRESET.articulation ? 'PxArticulationReducedCoordinate::setSolverIterationCounts, position iterations (TGS: substeps)'
      : `PxRigidDynamic::setSolverIterationCounts on every body, position iterations${PRESET.solver === 'TGS' ? ' (TGS: substeps)' : ''}` },
  // From 1: PhysX accepts 0, but the jointed car's figures at 0 equal those at 1 to every digit
  // (car.circle, PGS), so 0 is not a setting of its own.
  { key: 'velocity_iterations', vehicle: 'car', kind: 'integer', role: 'solver_iterations', min: 1, max: 255, default: String(PRESET.velocity_iterations),
    help: 'the same call, velocity iterations' },
  { key: 'solver', vehicle: 'car', kind: 'choice', choices: ['PGS', 'TGS'], default: PRESET.solver,
    help: 'PxSceneDesc::solverType: PGS (projected Gauss-Seidel, the scene default) or TGS (temporal Gauss-Seidel)' },
  { key: 'ground', vehicle: 'car', kind: 'choice', choices: ['box', 'plane'], default: 'box',
    help: `the ground: a static PxBoxGeometry whose top face is z = 0, as large as the scenario needs (as the other single-precision adapters build it), or PhysX's PxPlaneGeometry` },
  ...(PRESET.articulation ? [{ key: 'drive_damping', vehicle: 'car', kind: 'real', min: 0, max: 1e12, min_exclusive: true,
    default: String(ARTICULATION_DRIVE_DAMPING), help: 'PxArticulationDrive damping of the steering and spin drives, N m s/rad (stiffness 0: a velocity drive)' }] : []),
];

// Collision filtering by PhysX's default filter shader: a pair collides when word0 of one shape's
// filter data has a bit of the other's word1 (either way); word2 is OR-ed into the pair flags.
const GROUND = 1, WHEEL = 2, DISK = 4;
const PF = PX.PxPairFlagEnum;
const REPORT = PF.eNOTIFY_TOUCH_FOUND | PF.eNOTIFY_TOUCH_PERSISTS | PF.eNOTIFY_CONTACT_POINTS;

const allocator = new PX.PxDefaultAllocator();
const errorCallback = new PX.PxDefaultErrorCallback();
const foundation = PX.CreateFoundation(PV, allocator, errorCallback);
const tolerances = new PX.PxTolerancesScale();  // length 1 m, speed 10 m/s: contact offset 0.02 m
const physics = PX.CreatePhysics(PV, foundation, tolerances);
PX.InitExtensions(physics);
const dispatcher = PX.DefaultCpuDispatcherCreate(0);  // the calling thread only: no worker threads in WASM
// Static functions of the bindings live on their classes' prototypes.
const helpers = PX.NativeArrayHelpers.prototype;
const ActorExt = PX.PxRigidActorExt.prototype, BodyExt = PX.PxRigidBodyExt.prototype;

// ---- small helpers: every PhysX value object made here is destroyed after use -------------------

function qmul(a, b) {
  const [ax, ay, az, aw] = a, [bx, by, bz, bw] = b;
  return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
    aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz];
}
const conj = (q) => [-q[0], -q[1], -q[2], q[3]];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const H = Math.SQRT1_2;
const X_TO_Z = [0, -H, 0, H];  // a joint turns about its frame's x: this frame's x is the parent's z
const X_TO_Y = [0, 0, H, H];   // ... and this one's x the parent's y

/// fn(t) with a PxTransform (p, q) made for it and destroyed after.
function withTransform(p, q, fn) {
  const v = new PX.PxVec3(p[0], p[1], p[2]), r = new PX.PxQuat(q[0], q[1], q[2], q[3]);
  const t = new PX.PxTransform(v, r);
  try {
    return fn(t);
  } finally {
    PX.destroy(t); PX.destroy(v); PX.destroy(r);
  }
}

/// A frame (p_W, q_W) of the world expressed in the frame of a body at pose {p, q}.
function localFrame(body, p_W, q_W) {
  const ic = conj(body.q);
  return { p: C.rotate(ic, sub(p_W, body.p)), q: qmul(ic, q_W) };
}

function readPose(actor) {
  const t = actor.getGlobalPose(), p = t.p, q = t.q;
  return { p: [p.x, p.y, p.z], q: [q.x, q.y, q.z, q.w] };
}

function readState(body) {
  const s = readPose(body);
  const v = body.getLinearVelocity(); s.v = [v.x, v.y, v.z];
  const w = body.getAngularVelocity(); s.w = [w.x, w.y, w.z];
  return s;
}

function setFilter(shape, word0, word1, word2 = 0) {
  const f = new PX.PxFilterData(word0, word1, word2, 0);
  shape.setSimulationFilterData(f);
  PX.destroy(f);
}

// ---- the world ----------------------------------------------------------------------------------

let world = null;  // { scene, actors, joints, materials, articulation, callback, owned, ... }

function newScene(gravity_W, solver, callback) {
  const desc = new PX.PxSceneDesc(tolerances);
  const g = new PX.PxVec3(gravity_W[0], gravity_W[1], gravity_W[2]);
  desc.gravity = g;
  desc.cpuDispatcher = dispatcher;
  desc.filterShader = PX.DefaultFilterShader();
  desc.solverType = solver === 'TGS' ? PX.PxSolverTypeEnum.eTGS : PX.PxSolverTypeEnum.ePGS;
  if (callback) desc.simulationEventCallback = callback;
  const scene = physics.createScene(desc);
  PX.destroy(g);
  PX.destroy(desc);
  if (!scene) throw new Error('PxPhysics::createScene failed');
  return scene;
}

function dropWorld() {
  if (!world) return;
  const w = world;
  world = null;
  for (const j of w.joints) j.release();
  if (w.articulation) {
    w.scene.removeArticulation(w.articulation);
    w.articulation.release();
  }
  for (const a of w.actors) {
    w.scene.removeActor(a);
    a.release();
  }
  w.scene.release();
  for (const m of w.materials) m.release();
  for (const o of w.owned) PX.destroy(o);
}

function material(mu) {
  // Static and dynamic friction both mu (liftcheck's Coulomb coefficient), restitution 0; PhysX
  // combines two materials' friction by their average (PxCombineMode::eAVERAGE, the default):
  // wheel and ground both mu give mu.
  const m = physics.createMaterial(mu, mu, 0);
  world.materials.push(m);
  return m;
}

/// A rigid dynamic body with one exclusive shape, its mass set and the inertia PhysX computes for
/// the shape at that mass; no damping, no sleeping, the iteration counts given.
function addDynamic(geometry, mat, p, q, mass_kg, filter, iters) {
  const body = withTransform(p, q, (t) => physics.createRigidDynamic(t));
  const shape = ActorExt.createExclusiveShape(body, geometry, mat);
  setFilter(shape, ...filter);
  BodyExt.setMassAndUpdateInertia(body, mass_kg);
  tuneBody(body, iters);
  world.scene.addActor(body);
  world.actors.push(body);
  return body;
}

function tuneBody(body, iters) {
  body.setLinearDamping(0);
  body.setAngularDamping(0);
  body.setMaxAngularVelocity(MAX_ANGULAR_VELOCITY);
  if (iters) {
    body.setSolverIterationCounts(iters.position_iterations, iters.velocity_iterations);
    body.setSleepThreshold(0);  // a parked car must not fall asleep
  }
}

function addGround(mu, kind, car, q0) {
  // A box whose top face is z = 0, centred under the start, as large as the scenario needs (as the
  // jolt and havok adapters build theirs), or PhysX's plane (x of its frame is the normal).
  const half = C.groundHalf_m(car);
  const ground = kind === 'plane' ? withTransform([0, 0, 0], X_TO_Z, (t) => physics.createRigidStatic(t))
    : withTransform([q0.x_m, q0.y_m, -0.5], [0, 0, 0, 1], (t) => physics.createRigidStatic(t));
  const geom = kind === 'plane' ? new PX.PxPlaneGeometry() : new PX.PxBoxGeometry(half, half, 0.5);
  const shape = ActorExt.createExclusiveShape(ground, geom, material(mu));
  PX.destroy(geom);
  setFilter(shape, GROUND, WHEEL, REPORT);  // contact reports for the wheel-ground pairs
  world.groundShape = shape.ptr;
  world.scene.addActor(ground);
  world.actors.push(ground);
}

// ---- the car --------------------------------------------------------------------------------------

function buildCar(req) {
  dropWorld();  // a build that fails leaves no world to step
  const knob = C.applySettings(KNOBS, req.settings, 'car');
  const { car: d, q0, servo, mu, gravity_W } = C.carRequest(req);
  const callback = groundForceCallback();
  world = { scene: null, actors: [], joints: [], materials: [], articulation: null, owned: [callback] };
  world.scene = newScene(gravity_W, knob.solver, callback);
  world.points = new PX.PxArray_PxContactPairPoint(64);
  world.owned.push(world.points);
  addGround(mu, knob.ground, d, q0);
  const wheelMat = material(mu), ghostMat = material(0);
  const R = d.R_m, l = d.l_m, w = d.track_m;
  const yaw = C.yawQuat(q0.phi_rad);
  const box = new PX.PxBoxGeometry(l / 2, w / 2, d.chassis_height_m / 2);
  const knuckleGeom = new PX.PxSphereGeometry(C.KNUCKLE_RADIUS_M);
  const wheelGeom = new PX.PxSphereGeometry(R);
  try {
    const parts = { chassis: { p: C.chassisPoint(q0, -l / 2, 0, R), q: yaw },
      fronts: C.frontWheels(d, q0.beta_rad).map(({ y_m, beta0_rad }) => ({ p: C.chassisPoint(q0, 0, y_m, R), q: C.yawQuat(q0.phi_rad + beta0_rad) })),
      rears: [1, -1].map((s) => ({ p: C.chassisPoint(q0, -l, s * w / 2, R), q: yaw })) };
    const geoms = { box, knuckleGeom, wheelGeom, wheelMat, ghostMat };
    world.car = PRESET.articulation ? articulatedCar(d, parts, geoms, servo, knob) : jointedCar(d, parts, geoms, servo, knob);
  } finally {
    PX.destroy(box); PX.destroy(knuckleGeom); PX.destroy(wheelGeom);
  }
  return carState(0);
}

/// The car from rigid bodies and PxRevoluteJoints (maximal coordinates).
function jointedCar(d, parts, g, servo, iters) {
  const chassis = addDynamic(g.box, g.ghostMat, parts.chassis.p, parts.chassis.q, d.chassis_mass_kg, [0, 0], iters);
  const wheel = (part) => addDynamic(g.wheelGeom, g.wheelMat, part.p, part.q, d.wheel_mass_kg, [WHEEL, GROUND, REPORT], iters);
  const pose = (part) => ({ p: part.p, q: part.q });
  const revolute = (a, pa, b, pb, p_W, q_W, limit_Nm) => {
    const fa = localFrame(pa, p_W, q_W), fb = localFrame(pb, p_W, q_W);
    const j = withTransform(fa.p, fa.q, (ta) => withTransform(fb.p, fb.q, (tb) => PX.RevoluteJointCreate(physics, a, ta, b, tb)));
    world.joints.push(j);
    if (limit_Nm > 0) {
      j.setRevoluteJointFlag(PX.PxRevoluteJointFlagEnum.eDRIVE_ENABLED, true);
      j.setConstraintFlag(PX.PxConstraintFlagEnum.eDRIVE_LIMITS_ARE_FORCES, true);  // without it the limit is an impulse
      j.setDriveForceLimit(limit_Nm);
      j.setDriveVelocity(0);
    }
    return j;
  };
  const fronts = parts.fronts.map((part) => {
    const knuckle = addDynamic(g.knuckleGeom, g.ghostMat, part.p, part.q, d.knuckle_mass_kg, [0, 0], iters);
    const body = wheel(part);
    const steer = revolute(chassis, pose(parts.chassis), knuckle, pose(part), part.p, X_TO_Z, servo.steer_Nm);
    const spin = revolute(knuckle, pose(part), body, pose(part), part.p, qmul(part.q, X_TO_Y), servo.spin_Nm);
    return { knuckle, wheel: body, steer, spin };
  });
  // The rear wheels on passive PxRevoluteJoints; in a braked run (servo.rear_brake_Nm > 0,
  // docs/protocol.md) each gets the front spin's drive: eDRIVE_ENABLED, setDriveVelocity(0) (the
  // wheel's spin relative to the chassis), setDriveForceLimit(brake torque) with
  // eDRIVE_LIMITS_ARE_FORCES. PhysX 5 API (PxRevoluteJoint.h, nvidia-omniverse.github.io/PhysX):
  // setDriveForceLimit "sets the maximum torque the drive can exert. The value set here may be used
  // either as an impulse limit or a force limit, depending on the flag
  // PxConstraintFlag::eDRIVE_LIMITS_ARE_FORCES"; PxRevoluteJointFlag::eDRIVE_ENABLED "enable the
  // drive". Unbraked (0): passive joints as before.
  const rears = parts.rears.map((part) => {
    const body = wheel(part);
    revolute(chassis, pose(parts.chassis), body, pose(part), part.p, qmul(parts.chassis.q, X_TO_Y), servo.rear_brake_Nm);
    return body;
  });
  return {
    chassis, fronts, rears,
    // PxRevoluteJoint's drive velocity is actor1's (the knuckle's, the wheel's) relative to actor0
    // about the joint's x axis (PhysX 5; measured: +rate turns the child by +rate).
    drive: (k, spin, steer) => { fronts[k].spin.setDriveVelocity(spin); fronts[k].steer.setDriveVelocity(steer); },
  };
}

/// The car as one reduced-coordinate articulation: the chassis its floating root, each knuckle a
/// link on a revolute joint about the chassis z, each wheel a link on a revolute joint about its
/// knuckle's (or the chassis's) y.
function articulatedCar(d, parts, g, servo, iters) {
  const art = physics.createArticulationReducedCoordinate();
  art.setSolverIterationCounts(iters.position_iterations, iters.velocity_iterations);
  art.setSleepThreshold(0);
  art.setArticulationFlag(PX.PxArticulationFlagEnum.eDRIVE_LIMITS_ARE_FORCES, true);
  art.setArticulationFlag(PX.PxArticulationFlagEnum.eDISABLE_SELF_COLLISION, true);
  world.articulation = art;
  const link = (parent, part, geom, mat, mass_kg, filter) => {
    const l = withTransform(part.p, part.q, (t) => art.createLink(parent, t));
    const shape = ActorExt.createExclusiveShape(l, geom, mat);
    setFilter(shape, ...filter);
    BodyExt.setMassAndUpdateInertia(l, mass_kg);
    tuneBody(l, null);
    return l;
  };
  const TWIST = PX.PxArticulationAxisEnum.eTWIST;
  const joint = (child, parentPart, childPart, p_W, q_W, limit_Nm) => {
    const j = child.getInboundJoint();
    j.setJointType(PX.PxArticulationJointTypeEnum.eREVOLUTE);
    j.setMotion(TWIST, PX.PxArticulationMotionEnum.eFREE);
    const fp = localFrame(parentPart, p_W, q_W), fc = localFrame(childPart, p_W, q_W);
    withTransform(fp.p, fp.q, (t) => j.setParentPose(t));
    withTransform(fc.p, fc.q, (t) => j.setChildPose(t));
    j.setMaxJointVelocity(MAX_ANGULAR_VELOCITY);
    if (limit_Nm > 0) {
      const drive = new PX.PxArticulationDrive(0, iters.drive_damping, limit_Nm, PX.PxArticulationDriveTypeEnum.eFORCE);
      j.setDriveParams(TWIST, drive);
      PX.destroy(drive);
      j.setDriveVelocity(TWIST, 0);
    }
    return j;
  };
  const chassis = link(null, parts.chassis, g.box, g.ghostMat, d.chassis_mass_kg, [0, 0]);
  const fronts = parts.fronts.map((part) => {
    const knuckle = link(chassis, part, g.knuckleGeom, g.ghostMat, d.knuckle_mass_kg, [0, 0]);
    const steer = joint(knuckle, parts.chassis, part, part.p, X_TO_Z, servo.steer_Nm);
    const wheel = link(knuckle, part, g.wheelGeom, g.wheelMat, d.wheel_mass_kg, [WHEEL, GROUND, REPORT]);
    const spin = joint(wheel, part, part, part.p, qmul(part.q, X_TO_Y), servo.spin_Nm);
    return { knuckle, wheel, steer, spin };
  });
  // The rear wheels on free revolute joints; in a braked run (servo.rear_brake_Nm > 0,
  // docs/protocol.md) each gets the front spin's drive: PxArticulationDrive(stiffness 0, damping
  // drive_damping, maxForce = brake torque, eFORCE) on eTWIST with setDriveVelocity(eTWIST, 0) (the
  // wheel's spin relative to the chassis), eDRIVE_LIMITS_ARE_FORCES set on the articulation above.
  // PhysX 5.6.1 API (PxSolverDefs.h, struct PxArticulationDrive,
  // nvidia-omniverse.github.io/PhysX/physx/5.6.1/_api_build/structPxArticulationDrive.html): damping
  // is "the derivative gain of the implicit PD controller", torque/(rad/s) for a rotational axis
  // under eFORCE; maxForce the drive's force (torque) limit. Unbraked (0): no drive, as before.
  const rears = parts.rears.map((part) => {
    const wheel = link(chassis, part, g.wheelGeom, g.wheelMat, d.wheel_mass_kg, [WHEEL, GROUND, REPORT]);
    joint(wheel, parts.chassis, part, part.p, qmul(parts.chassis.q, X_TO_Y), servo.rear_brake_Nm);
    return wheel;
  });
  if (!world.scene.addArticulation(art)) throw new Error('PxScene::addArticulation failed');
  return {
    chassis, fronts, rears,
    // An articulation joint's velocity is the child's relative to the parent about the axis.
    drive: (k, spin, steer) => { fronts[k].spin.setDriveVelocity(TWIST, spin); fronts[k].steer.setDriveVelocity(TWIST, steer); },
  };
}

function carState(engine_s) {
  const { chassis, fronts, rears } = world.car;
  const cq = readPose(chassis).q;
  const fs = fronts.map((f) => ({ k: readPose(f.knuckle).q, w: readState(f.wheel) }));
  return C.carReply(engine_s, fs.map((f) => C.twist(f.k, f.w.q, 1)), fs.map((f) => C.twist(cq, f.k, 2)), cq,
    fs.map((f) => f.w), rears.map(readState));
}

function simulate(dt_s) {
  world.scene.simulate(dt_s);
  world.scene.fetchResults(true);
}

function stepCar(req) {
  const { spin, steer, dt_s } = C.carStep(req);
  world.car.fronts.forEach((_, k) => world.car.drive(k, spin[k], steer[k]));
  world.ground = { impulse: [0, 0, 0], missing: null, js_s: 0 };
  const step_s = timed(() => simulate(dt_s));
  const g = world.ground;
  // engine_s: the step less the adapter's own JavaScript in the report callback (PhysX's making
  // of the reports stays counted).
  const reply = carState(Math.max(0, step_s - g.js_s));
  if (g.missing) {  // a contact that pushed without its friction record: no force rather than half of one
    if (!world.warned) process.stderr.write(`physx adapter: ground_force_W left out: ${g.missing}\n`);
    world.warned = true;
  } else {
    reply.ground_force_W = g.impulse.map((j) => j / dt_s);
  }
  const v = world.car.chassis.getLinearVelocity();
  reply.v_chassis_W = [v.x, v.y, v.z];
  return reply;
}

// ---- the car's contact forces ---------------------------------------------------------------------

// PhysX 5.6 struct layouts in the WASM32 build (PxSimulationEventCallback.h, PxContact.h).
const PAIR_CONTACT_PATCHES = 8, PAIR_FRICTION_PATCHES = 20, PAIR_CONTACT_COUNT = 28, PAIR_PATCH_COUNT = 29;
const FRICTION_PATCH_BYTES = 52, ANCHOR_IMPULSES = 24, ANCHOR_COUNT = 48;
const CPF = PX.PxContactPairFlagEnum;

/// A simulation event callback that hears contacts only (onContact(header, pairs, nbPairs)).
function contactsOnly(onContact) {
  const cb = new PX.PxSimulationEventCallbackImpl();
  cb.onConstraintBreak = () => {};
  cb.onWake = () => {};
  cb.onSleep = () => {};
  cb.onTrigger = () => {};
  cb.onContact = onContact;
  return cb;
}

/// The wheel-ground impulses of the step, summed on the wheels (called from fetchResults).
function groundForceCallback() {
  return contactsOnly((header, pairs, nbPairs) => {
    const g = world.ground;
    if (!g) return;
    const t0 = process.hrtime.bigint();
    try {
      readGroundPairs(g, pairs, nbPairs);
    } finally {
      g.js_s += Number(process.hrtime.bigint() - t0) * 1e-9;
    }
  });
}

/// Adds the ground's impulses on the wheels in the step's reported pairs to g.impulse.
function readGroundPairs(g, pairs, nbPairs) {
  for (let i = 0; i < nbPairs; i++) {
    const pair = helpers.getContactPairAt(pairs, i);
    const flags = pair.flags;
    if (flags.isSet(CPF.eREMOVED_SHAPE_0) || flags.isSet(CPF.eREMOVED_SHAPE_1)) continue;
    const s0 = pair.get_shapes(0).ptr, s1 = pair.get_shapes(1).ptr;
    if (s0 !== world.groundShape && s1 !== world.groundShape) continue;
    // Shape 0 takes +impulse: the normal "points from the second shape to the first shape"
    // (PxContactPairPoint::normal) and the friction rows act on body 0 with + (the solver's
    // convention for both): on the wheel, +impulse if it is shape 0, -impulse if the ground is.
    const sign = s0 === world.groundShape ? -1 : 1;
    const n = pair.extractContacts(world.points.begin(), world.points.size());
    let normal = 0;
    for (let k = 0; k < n; k++) {
      const j = world.points.get(k).impulse;
      g.impulse[0] += sign * j.x; g.impulse[1] += sign * j.y; g.impulse[2] += sign * j.z;
      normal += Math.abs(j.x) + Math.abs(j.y) + Math.abs(j.z);
    }
    // The friction anchors (PxContactPair::extractFrictionAnchors, read from the WASM memory).
    const base = pair.ptr, u8 = PX.HEAPU8, dv = new DataView(u8.buffer);
    if (PHYSX_VERSION !== '5.6.1') {  // the byte offsets below are 5.6.1's (wasm32)
      g.missing = `PhysX ${PHYSX_VERSION}: this adapter reads PxContactPair's friction anchors at PhysX 5.6.1's layout only`;
      return;
    }
    if (u8[base + PAIR_CONTACT_COUNT] !== pair.contactCount || u8[base + PAIR_PATCH_COUNT] !== pair.patchCount
      || dv.getUint32(base, true) !== s0 || dv.getUint32(base + 4, true) !== s1) {
      g.missing = 'the PxContactPair in memory is not laid out as this adapter reads it (PhysX 5.6, wasm32)';
      return;  // no throwing through PhysX's frames
    }
    const patches = dv.getUint32(base + PAIR_CONTACT_PATCHES, true), friction = dv.getUint32(base + PAIR_FRICTION_PATCHES, true);
    if (!patches || !friction) {
      if (normal > 0) g.missing = 'a wheel-ground pair with a normal impulse reported no friction patches (PxContactPair::frictionPatches NULL)';
      continue;
    }
    for (let p = 0; p < pair.patchCount; p++) {
      const fp = friction + p * FRICTION_PATCH_BYTES;
      const anchors = dv.getUint32(fp + ANCHOR_COUNT, true);
      if (anchors > 2) {
        g.missing = `PxFrictionPatch::anchorCount ${anchors} > MAX_ANCHOR_COUNT 2: not the layout this adapter reads`;
        return;
      }
      for (let a = 0; a < anchors; a++) {
        const at = fp + ANCHOR_IMPULSES + 12 * a;
        g.impulse[0] += sign * dv.getFloat32(at, true);
        g.impulse[1] += sign * dv.getFloat32(at + 4, true);
        g.impulse[2] += sign * dv.getFloat32(at + 8, true);
      }
    }
    // A pushing pair may come with no friction anchor (PhysX leaves a pair's friction records
    // empty where its friction patch does not match the contact patch: on physx's car.circle at
    // t = 5.426 s): that step counts its normal impulse alone, as the report gives it.
  }
}

// ---- the disks ----------------------------------------------------------------------------------

/// The step's M-N contacts, from PhysX's contact reports (called from fetchResults).
function contactCallback() {
  return contactsOnly((header, pairs, nbPairs) => {
    const seen = world.contacts;
    for (let i = 0; i < nbPairs; i++) {
      const pair = helpers.getContactPairAt(pairs, i);
      const n = pair.extractContacts(world.points.begin(), world.points.size());
      for (let k = 0; k < n; k++) {
        seen.count += 1;
        seen.distance_min_m = Math.min(seen.distance_min_m, world.points.get(k).separation);
      }
    }
  });
}

function buildDisks(req) {
  dropWorld();
  C.applySettings(KNOBS, req.settings, 'disks');
  const { radius_m, cM0, cN0, mu_MN } = C.diskRequest(req);
  const callback = contactCallback();
  world = { scene: null, actors: [], joints: [], materials: [], articulation: null, owned: [callback] };
  world.scene = newScene([0, 0, 0], PRESET.solver, callback);
  world.points = new PX.PxArray_PxContactPairPoint(64);
  world.owned.push(world.points);
  const mat = material(mu_MN);  // mu_MN on both (their average): 0, frictionless, in every scenario
  const geom = new PX.PxSphereGeometry(radius_m);
  const iters = { position_iterations: PRESET.position_iterations, velocity_iterations: PRESET.velocity_iterations };
  try {
    world.M = addDynamic(geom, mat, [cM0[0], cM0[1], 0], [0, 0, 0, 1], 1, [DISK, DISK, REPORT], iters);
    const L = PX.PxRigidDynamicLockFlagEnum;
    for (const f of [L.eLOCK_LINEAR_Z, L.eLOCK_ANGULAR_X, L.eLOCK_ANGULAR_Y, L.eLOCK_ANGULAR_Z]) world.M.setRigidDynamicLockFlag(f, true);
    // And a zero mass-space inertia tensor, which PhysX reads as infinite inertia: under TGS the
    // angular lock flags alone let M turn under friction (mu_MN 0.5: 0.049 rad/s at 16 position
    // iterations, 0.0054 rad/s at 32; PGS held it), the protocol asks for at most 1e-6 rad/s.
    const zero = new PX.PxVec3(0, 0, 0);
    world.M.setMassSpaceInertiaTensor(zero);
    PX.destroy(zero);
    world.N = withTransform([cN0[0], cN0[1], 0], [0, 0, 0, 1], (t) => physics.createRigidDynamic(t));
    const shape = ActorExt.createExclusiveShape(world.N, geom, mat);
    setFilter(shape, DISK, DISK, REPORT);
    world.N.setRigidBodyFlag(PX.PxRigidBodyFlagEnum.eKINEMATIC, true);
    world.scene.addActor(world.N);
    world.actors.push(world.N);
  } finally {
    PX.destroy(geom);
  }
  // Reused for every step's commands (their fields set in place).
  world.vM = new PX.PxVec3(0, 0, 0);
  world.pN = new PX.PxVec3(0, 0, 0);
  world.qN = new PX.PxQuat(0, 0, 0, 1);
  world.target = new PX.PxTransform(world.pN, world.qN);
  world.owned.push(world.vM, world.pN, world.qN, world.target);
  return diskState();
}

function diskState() {
  const m = readPose(world.M).p, n = readPose(world.N).p, w = world.M.getAngularVelocity();
  return { cM: [m[0], m[1]], cN: [n[0], n[1]], wM: [w.x, w.y, w.z] };
}

function stepDisks(req) {
  const { vM, cN_next, dt_s } = C.diskStep(req);
  const v = world.vM;
  v.x = vM[0]; v.y = vM[1]; v.z = 0;
  world.M.setLinearVelocity(v);
  const p = world.target.p;
  p.x = cN_next[0]; p.y = cN_next[1]; p.z = 0;
  world.N.setKinematicTarget(world.target);
  world.contacts = { count: 0, distance_min_m: Infinity };
  const engine_s = timed(() => simulate(dt_s));
  const c = world.contacts;
  const contacts = C.contactsReply(c);
  return { engine_s, ...diskState(), contacts };
}

// ---- hello --------------------------------------------------------------------------------------

const FIXED = {
  default: 'PhysX as shipped: PGS (PxSolverType::ePGS, the scene default), 4 position and 1 velocity iterations per body (PxRigidDynamic::setSolverIterationCounts, "Default: 4 position iterations, 1 velocity iteration"), patch friction, PCM contacts, contact offset 0.02 m, rest offset 0',
  tgs: 'TGS (PxSolverType::eTGS: "can lead to improved convergence and handle large mass ratios, long chains and jointed systems better"), 16 position and 1 velocity iterations per body: more position iterations are what setSolverIterationCounts advises for jointed bodies and what PhysX\'s maintainers advise for jointed chains with mass ratios, with TGS (NVIDIAGameWorks/PhysX issue 308); 16/1 is Isaac Sim\'s rigid-body default (PhysxSchema PhysxRigidBodyAPI solverPositionIterationCount 16, solverVelocityIterationCount 1); everything else as shipped',
  articulation: 'one PxArticulationReducedCoordinate (floating base), TGS (Isaac Sim\'s scene default), 32 position and 1 velocity iterations (Isaac Sim\'s articulation default: PhysxSchema PhysxArticulationAPI solverPositionIterationCount 32, solverVelocityIterationCount 1; the count PhysX\'s SnippetArticulationRC sets)',
};

serve({
  hello: () => ({
    engine: 'NVIDIA PhysX', version: `${PHYSX_VERSION} (physx-js-webidl ${VERSION})`, precision: 'float32',
    vehicles: ['car', 'disks'], four_wheels: true, brakes: true, settings: KNOBS,
    fixed: [
      ['configuration', FIXED[CONFIG]],
      ['stepping', 'PxScene::simulate(dt) then fetchResults(true): one fixed step, no substepping beyond the solver\'s own, the state read after it; one CPU thread (DefaultCpuDispatcherCreate(0))'],
      ['joints', PRESET.articulation
        ? `articulation links: chassis (root, floating), per front wheel a knuckle on a revolute joint about the chassis z and the wheel on a revolute joint about the knuckle y, rear wheels on revolute joints about the chassis y; front joints (and a braked run\'s rear joints, at velocity 0 and the brake\'s torque) driven by PxArticulationDrive(stiffness 0, damping ${ARTICULATION_DRIVE_DAMPING}, maxForce = the servo torque, eFORCE) with setDriveVelocity, eDRIVE_LIMITS_ARE_FORCES, self-collision off`
        : 'PxRevoluteJoint steering (knuckle about the chassis z) and front-wheel spin (about the knuckle y), eDRIVE_ENABLED velocity drives, setDriveForceLimit(servo torque) with PxConstraintFlag::eDRIVE_LIMITS_ARE_FORCES (without it the limit is an impulse), setDriveVelocity(rate) (actor1 relative to actor0); passive PxRevoluteJoints for the rear wheels (a braked run: the same velocity drives at 0, force limit the brake\'s torque); jointed bodies do not collide'],
      ['bodies', `chassis box of the chassis mass, knuckle a ${C.KNUCKLE_RADIUS_M.toFixed(4)} m sphere of knuckle_mass_kg (both collide with nothing: filter data 0), sphere wheels of wheel_mass_kg; inertias from PxRigidBodyExt::setMassAndUpdateInertia; angular damping 0 (PhysX's default 0.05 would brake the wheels), linear damping 0, max angular velocity ${MAX_ANGULAR_VELOCITY} rad/s (default 100), sleep threshold 0 (a parked car must not sleep)`],
      ['friction', 'PxMaterial static = dynamic friction = mu on wheels and ground, restitution 0; PhysX averages two materials\' coefficients (PxCombineMode::eAVERAGE, the default): mu'],
      ['ground', 'a static PxBoxGeometry, top face z = 0, 60 m square (or 20 l) centred under the start (knob ground: box | plane, PhysX\'s PxPlaneGeometry)'],
      ['contact forces', `each car step reply's ground_force_W: the wheel-ground impulses of the step just solved over dt, from PhysX's own contact reports (PxSimulationEventCallback::onContact on the wheel-ground pairs, eNOTIFY_TOUCH_FOUND | eNOTIFY_TOUCH_PERSISTS | eNOTIFY_CONTACT_POINTS via the default filter shader's word2), summed over every pair, signed as acting on the wheel (${PRESET.articulation ? 'articulation wheel links' : 'wheel bodies'}): the normal part from PxContactPair::extractContacts (PxContactPairPoint::impulse is normal * the applied normal impulse only), the friction part from the pair's friction anchors (PxFrictionPatch::anchorImpulses, world frame, what the header-inline PxContactPair::extractFrictionAnchors returns; written by the ${PRESET.solver} solver's contact write-back since PhysX 5.4), read from the WASM memory with PhysX 5.6's struct layouts because the bindings export neither extractFrictionAnchors nor PxContactPair::frictionPatches (layout checked against the bound fields on every pair; a pushing contact without friction records leaves ground_force_W out). v_chassis_W: the chassis ${PRESET.articulation ? 'root link' : 'body'}'s getLinearVelocity (centre of mass). Requesting the reports leaves the simulation bit-identical (same poses on car.circle, cycle, slope, coulomb, yawed-slide). engine_s leaves out the adapter's JavaScript in the report callback`],
      ['disks', `M a PxRigidDynamic sphere of 1 kg, PxRigidDynamicLockFlag eLOCK_LINEAR_Z and eLOCK_ANGULAR_X/Y/Z and a zero mass-space inertia tensor (infinite inertia: under TGS the lock flags alone let M turn under friction), setLinearVelocity(command) before each step, ${PRESET.solver} at ${PRESET.position_iterations}/${PRESET.velocity_iterations} iterations; N kinematic (eKINEMATIC), setKinematicTarget(cN_next); material friction mu_MN on both; contacts from PxSimulationEventCallback::onContact (eNOTIFY_TOUCH_FOUND | eNOTIFY_TOUCH_PERSISTS | eNOTIFY_CONTACT_POINTS via the default filter shader), each point of PxContactPair::extractContacts, signed distance = its separation (points within the shapes' 0.02 m contact offsets included)`],
      ['four wheels', 'two front wheels at +-track/2, each on its own knuckle and joints as above, built at its Ackermann angle (or at beta when steered in parallel)'],
    ],
  }),
  car: buildCar,
  disks: buildDisks,
  stepCar,
  stepDisks,
});
