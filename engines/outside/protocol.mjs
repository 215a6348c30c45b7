// The liftcheck engine protocol (docs/protocol.md), version 1: one JSON request per line on
// standard input, one JSON reply per line on standard output. An adapter supplies an object with
// hello(), car(request), disks(request) and step(request) (the step of whichever world was built
// last); this loop does the framing, the timing of nothing but the adapter's own calls, and the
// error replies. Everything the adapter logs goes to standard error.
import { createInterface } from 'node:readline';

export const PROTOCOL = 1;

function finite(value, where) {
  if (typeof value === 'number' && !Number.isFinite(value)) throw new Error(`${where} is not finite`);
  if (Array.isArray(value)) value.forEach((v, i) => finite(v, `${where}[${i}]`));
  else if (value && typeof value === 'object') for (const [k, v] of Object.entries(value)) finite(v, `${where}.${k}`);
}

export async function serve(adapter) {
  console.log = console.error;  // keep standard output for replies only
  const out = (obj) => process.stdout.write(JSON.stringify(obj) + '\n');
  const lines = createInterface({ input: process.stdin, crlfDelay: Infinity });
  for await (const line of lines) {
    let req;
    try {
      req = JSON.parse(line);
    } catch (e) {
      out({ ok: false, error: `request is not JSON: ${e.message}` });
      continue;
    }
    try {
      let reply;
      switch (req.op) {
        case 'hello':
          if (req.protocol !== PROTOCOL) throw new Error(`protocol ${req.protocol} asked, this adapter speaks ${PROTOCOL}`);
          reply = { protocol: PROTOCOL, ...(await adapter.hello()) };
          break;
        case 'car': reply = await adapter.car(req); break;
        case 'disks': reply = await adapter.disks(req); break;
        case 'step': reply = adapter.step(req); break;
        case 'bye': out({ ok: true }); process.exit(0);
        default: throw new Error(`unknown op '${req.op}'`);
      }
      finite(reply, 'reply');
      out({ ok: true, ...reply });
    } catch (e) {
      out({ ok: false, error: String(e && e.message ? e.message : e).split('\n')[0] });
    }
  }
}

/// Seconds spent in fn(), for the reply's engine_s (the engine's own stepping time).
export function timed(fn) {
  const t0 = process.hrtime.bigint();
  fn();
  return Number(process.hrtime.bigint() - t0) * 1e-9;
}
