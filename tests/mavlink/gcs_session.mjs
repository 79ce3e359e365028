// What the node-mavlink tests of tern's mission protocol, commands and metadata share
// (test_gcs_mission.mjs, test_gcs_fence.mjs, test_gcs_metadata.mjs): their report, the flight
// they talk to, and a ground station's side of the mission protocol and the command protocol.
//
//   const { check, failures } = reporter()
//   const flight = flyWithGcs(tern, mission, work, gcs, seconds)   // tern fly --realtime --gcs
//   const m = missionClient(gcs)   // item, upload, download, command, differences
//   ...
//   await flight.finish(check)     // SIGINT, its output, its exit checked
//   process.exit(report(failures, gcs))
import { spawn } from 'node:child_process'
import fs from 'node:fs'
import path from 'node:path'
import { common } from 'node-mavlink'

/** The failures so far and the check that records one (one line per check, ok or FAIL). */
export function reporter() {
  const failures = []
  const check = (ok, what) => {
    if (!ok) failures.push(what)
    console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`)
  }
  return { failures, check }
}

/** The exit code after the checks: 0, or 1 with the number of failures said. */
export function report(failures, gcs) {
  gcs.close()
  if (failures.length) console.log(`${failures.length} failure(s)`)
  return failures.length ? 1 : 0
}

/** `tern fly MISSION --realtime --duration SECONDS --gcs` talking to `gcs` (flight time `speed`
 * times wall time, `extra` options after), its log in WORK/runs. */
export function flyWithGcs(tern, mission, work, gcs, seconds, speed = 1, extra = []) {
  fs.mkdirSync(work, { recursive: true })
  const logDir = path.join(work, 'runs')
  const child = spawn(tern, ['fly', mission, '--realtime', '--speed', String(speed), '--duration', String(seconds), '--log-dir', logDir, '-q',
    '--gcs', `127.0.0.1:${gcs.port}`, '--gcs-bind', '127.0.0.1:0', ...extra], { stdio: ['ignore', 'pipe', 'inherit'] })
  let out = ''
  child.stdout.on('data', (d) => { out += d })
  const exited = new Promise((resolve) => child.on('exit', (code, signal) => resolve({ code, signal })))
  return {
    logDir,
    /** Stops the flight (SIGINT), prints its output and checks that it ended cleanly; the output. */
    async finish(check) {
      child.kill('SIGINT')
      const { code, signal } = await exited
      console.log(out.trim())
      check(code === 0 || code === 130 || signal === 'SIGINT', `tern fly ended (code ${code}, signal ${signal})`)
      return out
    },
  }
}

const same = (a, b) => (Number.isNaN(a) && Number.isNaN(b)) || a === b

/** A ground station's side of the mission and command protocols on `gcs` (vehicle `system`, autopilot 1). */
export function missionClient(gcs, system = 1) {
  const R = common.MavMissionResult
  const target = (m) => Object.assign(m, { targetSystem: system, targetComponent: 1 })
  /** A MISSION_ITEM_INT; z and the params travel as float32: the values a GCS holds after sending them. */
  function item(seq, command, frame, lat, lon, z, params = [0, 0, 0, 0], missionType = 0) {
    const it = target(new common.MissionItemInt())
    Object.assign(it, { seq, command, frame, x: Math.round(lat * 1e7), y: Math.round(lon * 1e7), z: Math.fround(z), current: 0, autocontinue: 1, missionType })
    ;[it.param1, it.param2, it.param3, it.param4] = params.map(Math.fround)
    return it
  }
  /** Uploads `items` as list `missionType`, answering every MISSION_REQUEST_INT of it; the ACK. */
  async function upload(items, missionType = 0, ms = 5000) {
    const stop = gcs.listen('MISSION_REQUEST_INT', (r) => { if (r.missionType === missionType && r.seq < items.length) gcs.send(items[r.seq]) })
    const ack = gcs.next('MISSION_ACK', (a) => a.missionType === missionType, ms)
    gcs.send(Object.assign(target(new common.MissionCount()), { count: items.length, missionType }))
    try {
      return await ack
    } finally {
      stop()
    }
  }
  /** Downloads list `missionType` item by item. */
  async function download(missionType = 0) {
    const countP = gcs.next('MISSION_COUNT', (c) => c.missionType === missionType, 3000)
    gcs.send(Object.assign(target(new common.MissionRequestList()), { missionType }))
    const { count } = await countP
    const items = []
    for (let seq = 0; seq < count; seq++) {
      const p = gcs.next('MISSION_ITEM_INT', (d) => d.seq === seq && d.missionType === missionType, 3000)
      gcs.send(Object.assign(target(new common.MissionRequestInt()), { seq, missionType }))
      items.push(await p)
    }
    gcs.send(Object.assign(target(new common.MissionAck()), { type: R.ACCEPTED, missionType }))
    return items
  }
  /** The fields in which `back` differs from `sent`, one line each. */
  function differences(sent, back) {
    if (sent.length !== back.length) return [`${back.length} items, not ${sent.length}`]
    const fields = ['seq', 'command', 'frame', 'x', 'y', 'z', 'param1', 'param2', 'param3', 'param4', 'autocontinue', 'missionType']
    return sent.flatMap((s, i) => fields.filter((f) => !same(s[f], back[i][f])).map((f) => `item ${i} ${f}: ${s[f]} -> ${back[i][f]}`))
  }
  /** COMMAND_LONG (or COMMAND_INT with a frame and position); its COMMAND_ACK's result. */
  async function command(id, params = [], frame = null, position = null) {
    const c = target(frame === null ? new common.CommandLong() : new common.CommandInt())
    c.command = id
    for (let k = 0; k < 7; k++) c[`_param${k + 1}`] = params[k] ?? 0
    if (frame !== null) {
      c.frame = frame
      ;[c._param5, c._param6, c._param7] = position
    }
    const ack = gcs.next('COMMAND_ACK', (d) => d.command === id, 5000)
    gcs.send(c)
    return (await ack).result
  }
  return { target, item, upload, download, differences, command }
}
