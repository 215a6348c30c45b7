// What the Jolt and Havok adapters share: the car's geometry in the chassis frame of
// docs/protocol.md (x forward along the tie rod, y left, z up, origin at the front-axle centre),
// quaternion arithmetic on [x, y, z, w], and the checking of knob values against their
// declaration (a value out of range is refused, never clamped).

/// Unit quaternion [x, y, z, w] of a rotation by angle_rad about the world z axis.
export function yaw_quat(angle_rad) {
  return [0, 0, Math.sin(0.5 * angle_rad), Math.cos(0.5 * angle_rad)];
}

/// The vector v = [x, y, z] rotated by the unit quaternion q = [x, y, z, w].
export function rotate(q, v) {
  const [qx, qy, qz, qw] = q;
  // t = 2 (q_vec x v); v' = v + w t + q_vec x t
  const tx = 2 * (qy * v[2] - qz * v[1]), ty = 2 * (qz * v[0] - qx * v[2]), tz = 2 * (qx * v[1] - qy * v[0]);
  return [v[0] + qw * tx + (qy * tz - qz * ty), v[1] + qw * ty + (qz * tx - qx * tz), v[2] + qw * tz + (qx * ty - qy * tx)];
}

/// Heading of a body (the angle of its x axis in the world xy plane), rad.
export function heading(q) {
  const x = rotate(q, [1, 0, 0]);
  return Math.atan2(x[1], x[0]);
}

/// Angle of body b about the unit axis a (world frame) relative to body a's orientation, from
/// the two bodies' orientations: the twist of conj(q_a) q_b about a expressed in a's frame.
export function twist_angle(q_a, q_b, axis_in_a) {
  const [ax, ay, az, aw] = [-q_a[0], -q_a[1], -q_a[2], q_a[3]];
  const [bx, by, bz, bw] = q_b;
  const r = [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
             aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz];
  const s = r[0] * axis_in_a[0] + r[1] * axis_in_a[1] + r[2] * axis_in_a[2];
  return wrap(2 * Math.atan2(s, r[3]));
}

/// angle wrapped to (-pi, pi].
export function wrap(angle_rad) {
  let a = angle_rad % (2 * Math.PI);
  if (a > Math.PI) a -= 2 * Math.PI;
  if (a <= -Math.PI) a += 2 * Math.PI;
  return a;
}

/// Where the car's bodies start: world positions of points given in the chassis frame at q0.
export function chassis_to_world(q0) {
  const c = Math.cos(q0.phi_rad), s = Math.sin(q0.phi_rad);
  return (bx, by, bz) => [q0.x_m + c * bx - s * by, q0.y_m + s * bx + c * by, bz];
}

/// The knob values of a request: every declared knob of `vehicle` from `given` or its default,
/// each checked against its kind and range; an unknown key is refused.
export function apply_settings(declared, vehicle, given) {
  const mine = declared.filter((k) => k.vehicle === vehicle);
  for (const key of Object.keys(given || {}))
    if (!mine.some((k) => k.key === key)) throw new Error(`setting '${key}' is not a ${vehicle} setting of this configuration`);
  const out = {};
  for (const k of mine) {
    const text = given && key_in(given, k.key) ? String(given[k.key]) : k.default;
    out[k.key] = parse_setting(k, text);
  }
  return out;
}

function key_in(obj, key) {
  return Object.prototype.hasOwnProperty.call(obj, key);
}

function parse_setting(k, text) {
  if (k.kind === 'choice') {
    if (!k.choices.includes(text)) throw new Error(`setting ${k.key} = '${text}' is not one of ${k.choices.join(' | ')}`);
    return text;
  }
  const v = Number(text);
  const whole = k.kind === 'integer';
  if (text.trim() === '' || !Number.isFinite(v) || (whole && !Number.isInteger(v)))
    throw new Error(`setting ${k.key} = '${text}' is not ${whole ? 'a whole number' : 'a number'}`);
  const low_ok = k.min_exclusive ? v > k.min : v >= k.min;
  if (!low_ok || v > k.max)
    throw new Error(`setting ${k.key} = ${text} is outside ${k.min_exclusive ? '(' : '['}${k.min}, ${k.max}]`);
  return v;
}

/// The wheel-shape knob both adapters declare for the car (Bullet's `wheel`, same choices).
export const WHEEL_KNOB = { key: 'wheel', vehicle: 'car', kind: 'choice', choices: ['sphere', 'cylinder'], default: 'sphere',
  help: 'wheel collision shape: spheres of radius R, or cylinders of wheel_width_m about the axle' };

/// The wheel shape a car request asks for: the `wheel` knob where it is set, else car.wheel_shape
/// (the two must agree where both are given).
export function wheel_shape_of(req, knob) {
  const given = req.settings && Object.prototype.hasOwnProperty.call(req.settings, 'wheel');
  if (given && req.car.wheel_shape !== undefined && req.car.wheel_shape !== knob.wheel)
    throw new Error(`setting wheel = ${knob.wheel} disagrees with car.wheel_shape = ${req.car.wheel_shape}`);
  return given ? knob.wheel : req.car.wheel_shape;
}

/// Refuses a car request this adapter cannot build as asked.
export function check_car(req) {
  const c = req.car;
  if (!c) throw new Error('car request without "car"');
  for (const key of ['R_m', 'l_m', 'track_m', 'chassis_height_m', 'chassis_mass_kg', 'wheel_mass_kg', 'knuckle_mass_kg'])
    if (!(typeof c[key] === 'number' && c[key] > 0)) throw new Error(`car.${key} must be a positive number`);
  if (c.wheels !== 3 && c.wheels !== 4) throw new Error(`car.wheels = ${c.wheels} is not 3 (the tricycle) or 4`);
  if (c.wheel_shape !== undefined && c.wheel_shape !== 'sphere' && c.wheel_shape !== 'cylinder') throw new Error(`car.wheel_shape '${c.wheel_shape}' is not sphere | cylinder`);
  if (!(c.wheel_width_m > 0)) throw new Error('car.wheel_width_m must be positive');
  if (!(req.dt_s > 0)) throw new Error('dt_s must be positive');
  if (!(req.mu >= 0)) throw new Error('mu must be a number >= 0');
  if (!Array.isArray(req.gravity_W) || req.gravity_W.length !== 3) throw new Error('gravity_W must be [x, y, z]');
  for (const key of ['x_m', 'y_m', 'phi_rad', 'beta_rad'])
    if (typeof req.q0?.[key] !== 'number') throw new Error(`q0.${key} must be a number`);
  for (const key of ['spin_torque_max_Nm', 'steer_torque_max_Nm'])
    if (!(req.servo?.[key] > 0)) throw new Error(`servo.${key} must be positive`);
}

/// The steered front wheels in the chassis frame: the tricycle's one at the front-axle centre,
/// steered at beta; a four-wheel car's left and right at y = +-track/2, each at its Ackermann angle
/// atan2(l sin beta, l cos beta -+ (track/2) sin beta) (models/ackermann.hpp), or at beta itself
/// when steered in parallel.
export function front_wheels(car, beta_rad) {
  if (car.wheels === 3) return [{ y_m: 0, beta0_rad: beta_rad }];
  return [1, -1].map((side) => ({
    y_m: 0.5 * side * car.track_m,
    beta0_rad: car.parallel_steering ? beta_rad
      : Math.atan2(car.l_m * Math.sin(beta_rad), car.l_m * Math.cos(beta_rad) - side * 0.5 * car.track_m * Math.sin(beta_rad)),
  }));
}

/// The per-wheel rates of a car step: spin_radps[k] and steer_radps[k] for each front wheel k.
export function front_rates(req, n_front) {
  const out = [];
  for (let k = 0; k < n_front; ++k) {
    const spin = req.spin_radps?.[k], steer = req.steer_radps?.[k];
    if (typeof spin !== 'number' || typeof steer !== 'number') throw new Error(`car step needs spin_radps[${k}] and steer_radps[${k}]`);
    out.push({ spin, steer });
  }
  return out;
}

/// The protocol's car state from the engine's readings: per front wheel its spin joint angle,
/// steering angle and pose; the chassis heading; every wheel's body state (fronts, then rears).
export function car_reply(fronts, phi_rad, wheels) {
  const n = fronts.length;
  const pair = (f) => [f(fronts[0]), n === 2 ? f(fronts[1]) : 0];
  return {
    spin_joint_rad: pair((f) => f.spin_rad),
    steer_rad: pair((f) => f.steer_rad),
    x_m: fronts.reduce((s, f) => s + f.p[0], 0) / n,
    y_m: fronts.reduce((s, f) => s + f.p[1], 0) / n,
    z_m: Math.min(...fronts.map((f) => f.p[2])),
    phi_rad,
    rear_z_m: Math.min(wheels[n].hub_z_m, wheels[n + 1].hub_z_m),
    wheels,
  };
}

/// Half-size of the square ground box centred under the start, m: room for the scenarios' drives
/// (10 m paths, laps of the turning circle l / sin(beta)) and no more (float32 engines lose
/// contact precision on large shapes, docs/protocol.md).
export function ground_half_m(car) {
  return Math.max(30, 10 * car.l_m);
}

/// Inertia radius of the steering knuckle, m: a solid sphere of this radius has 1e-4 kg m^2 at
/// 0.05 kg, the built-in adapters' knuckle (engines/mujoco, engines/dart); it scales with the mass.
export const KNUCKLE_RADIUS_M = Math.sqrt(1e-4 / (0.4 * 0.05));
