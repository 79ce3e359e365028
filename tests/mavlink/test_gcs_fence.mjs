// tern's geofence and rally points over MAVLink (core/apps/mavlink/mission_protocol.hpp,
// fence_items.hpp; the failsafes, core/host/safety/failsafe.hpp; docs/ground-station.md) against
// node-mavlink playing the ground station, as QGroundControl's Plan view uploads a plan's three
// lists:
//
//   node test_gcs_fence.mjs TERN MISSION WORK_DIR
//
// It flies MISSION with `tern fly --realtime --gcs` and, waiting on messages (no sleeping):
//   - AUTOPILOT_VERSION claims MISSION_FENCE and MISSION_RALLY;
//   - a plan of all three lists (a mission, a fence of an inclusion polygon and an exclusion
//     circle, two rally points) uploads and reads back item for item, each answer carrying its
//     mission_type; SYS_STATUS then shows the geofence present, enabled and healthy;
//   - bad fences are refused with their MAV_MISSION_RESULT and a STATUSTEXT, the fence kept:
//     a polygon cut short, one that leaves home outside;
//   - once the mission has flown the aircraft 350 m out, NAV_RETURN_TO_LAUNCH flies to the
//     nearest rally point (the download lists a loiter there at its altitude);
//   - a fence uploaded around home while the aircraft is outside it: the breach is reported
//     (STATUSTEXT "failsafe geofence", SYS_STATUS's geofence bit unhealthy) within a second, and
//     acted on (the download lists the return);
//   - MISSION_CLEAR_ALL of FENCE and RALLY empties both lists.
// Exit 0 when all hold; 1 with one line per failure.
import { common } from 'node-mavlink'
import { openGcs } from './gcs_client.mjs'
import { flyWithGcs, missionClient, report, reporter } from './gcs_session.mjs'

const [tern, mission, work] = process.argv.slice(2)
if (!tern || !mission || !work) {
  console.error('usage: node test_gcs_fence.mjs TERN MISSION WORK_DIR')
  process.exit(2)
}
const { failures, check } = reporter()
const R = common.MavMissionResult
const Cmd = common.MavCmd
const Frame = common.MavFrame
const TYPE = { MISSION: 0, FENCE: 1, RALLY: 2 }
const GEOFENCE = 1 << 20 // MAV_SYS_STATUS_GEOFENCE
const M = 111320 // m per degree of latitude (flat earth: enough within a km)

const gcs = await openGcs()
const { target, item, upload, download, differences, command } = missionClient(gcs)
const metres = (a, b) => Math.hypot((a.lat - b.lat) * M, (a.lon - b.lon) * M * Math.cos((a.lat * Math.PI) / 180))

const flight = flyWithGcs(tern, mission, work, gcs, 120)

try {
  await gcs.next('HEARTBEAT', (d) => (d.baseMode & 128) !== 0, 20000) // armed: flying
  const versionP = gcs.next('AUTOPILOT_VERSION', () => true, 3000)
  await command(Cmd.REQUEST_MESSAGE, [148])
  const caps = BigInt((await versionP).capabilities)
  check((caps & 16384n) !== 0n && (caps & 32768n) !== 0n, `AUTOPILOT_VERSION capabilities ${caps} hold MISSION_FENCE and MISSION_RALLY`)
  const homeP = gcs.next('HOME_POSITION', () => true, 3000)
  await command(Cmd.REQUEST_MESSAGE, [242])
  const home = await homeP
  const h = { lat: home.latitude / 1e7, lon: home.longitude / 1e7 }
  const at = (north, east) => [h.lat + north / M, h.lon + east / (M * Math.cos((h.lat * Math.PI) / 180))]

  // ---- a plan's three lists, uploaded and read back ----
  const V = Cmd.NAV_FENCE_POLYGON_VERTEX_INCLUSION
  const fence = [
    item(0, V, Frame.GLOBAL_INT, ...at(1500, -1500), 0, [4, 0, 0, 0], TYPE.FENCE),
    item(1, V, Frame.GLOBAL_INT, ...at(1500, 1500), 0, [4, 0, 0, 0], TYPE.FENCE),
    item(2, V, Frame.GLOBAL_INT, ...at(-1500, 1500), 0, [4, 0, 0, 0], TYPE.FENCE),
    item(3, V, Frame.GLOBAL_INT, ...at(-1500, -1500), 0, [4, 0, 0, 0], TYPE.FENCE),
    item(4, Cmd.NAV_FENCE_CIRCLE_EXCLUSION, Frame.GLOBAL_INT, ...at(-1000, 1000), 0, [100, 0, 0, 0], TYPE.FENCE),
  ]
  const rally = [
    item(0, Cmd.NAV_RALLY_POINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(600, 0), 90, [0, 0, 0, 0], TYPE.RALLY),
    item(1, Cmd.NAV_RALLY_POINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(-600, 600), 80, [0, 0, 0, 0], TYPE.RALLY),
  ]
  const plan = [
    item(0, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(500, 0), 100, [0, 0, 0, NaN], TYPE.MISSION),
    item(1, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(500, 500), 100, [0, 0, 0, NaN], TYPE.MISSION),
    item(2, Cmd.NAV_LOITER_UNLIM, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(900, 500), 100, [0, 0, 80, NaN], TYPE.MISSION),
  ]
  check((await upload(plan, TYPE.MISSION)).type === R.ACCEPTED, 'the mission list accepted')
  const fenceAck = await upload(fence, TYPE.FENCE)
  check(fenceAck.type === R.ACCEPTED, `the fence (a 3-km square, a 100-m hole) accepted (${fenceAck.type}; ${gcs.texts.slice(-1)})`)
  check((await upload(rally, TYPE.RALLY)).type === R.ACCEPTED, 'two rally points accepted')
  for (const [name, sent] of [['MISSION', plan], ['FENCE', fence], ['RALLY', rally]]) {
    const diff = differences(sent, await download(TYPE[name]))
    check(diff.length === 0, `${name} reads back item for item (${diff.slice(0, 3).join('; ')})`)
  }
  const status = await gcs.next('SYS_STATUS', (s) => (s.onboardControlSensorsPresent & GEOFENCE) !== 0, 3000)
  check((status.onboardControlSensorsEnabled & GEOFENCE) !== 0 && (status.onboardControlSensorsHealth & GEOFENCE) !== 0,
    'SYS_STATUS: the geofence present, enabled and healthy')

  // ---- bad fences: refused, the fence kept ----
  const short = await upload(fence.slice(0, 3), TYPE.FENCE)
  check(short.type === R.INVALID, `a polygon of 4 vertices cut to 3: MAV_MISSION_INVALID (${short.type})`)
  const away = [0, 1, 2].map((k) => item(k, V, Frame.GLOBAL_INT, ...at(2000 + 100 * (k === 1), 2000 + 100 * (k === 2)), 0, [3, 0, 0, 0], TYPE.FENCE))
  const outsideText = gcs.next('STATUSTEXT', (d) => d.text.includes('leaves home outside'), 3000)
  check((await upload(away, TYPE.FENCE)).type === R.DENIED, 'a fence that leaves home outside: MAV_MISSION_DENIED')
  check((await outsideText).severity === common.MavSeverity.WARNING, '... and a STATUSTEXT says why')
  check(differences(fence, await download(TYPE.FENCE)).length === 0, 'the accepted fence is kept')

  // ---- RTL goes to the nearest rally point (once the mission has taken the aircraft near one) ----
  const pos = await gcs.next('GLOBAL_POSITION_INT', (g) => metres({ lat: g.lat / 1e7, lon: g.lon / 1e7 }, h) > 350, 60000)
  const p = { lat: pos.lat / 1e7, lon: pos.lon / 1e7 }
  const nearest = rally.map((r) => metres(p, { lat: r.x / 1e7, lon: r.y / 1e7 })).reduce((b, d, i, a) => (d < a[b] ? i : b), 0)
  check(await command(Cmd.NAV_RETURN_TO_LAUNCH) === common.MavResult.ACCEPTED, 'NAV_RETURN_TO_LAUNCH accepted')
  let listed = []
  for (let k = 0; k < 20 && !(listed.length === 1 && listed[0].command === Cmd.NAV_LOITER_UNLIM); k++) {
    await gcs.next('ATTITUDE', () => true, 3000)
    listed = await download(TYPE.MISSION)
  }
  const r = rally[nearest]
  check(listed.length === 1 && listed[0].command === Cmd.NAV_LOITER_UNLIM &&
    metres({ lat: listed[0].x / 1e7, lon: listed[0].y / 1e7 }, { lat: r.x / 1e7, lon: r.y / 1e7 }) < 1 && Math.abs(listed[0].z - r.z) < 0.5,
  `the return flies to rally point ${nearest}, the nearest, at its altitude (${listed.map((i) => `${i.command}@${i.z}`).join(' ')})`)

  // ---- a breach: reported and acted on within a second ----
  const far = await gcs.next('GLOBAL_POSITION_INT', () => true, 3000)
  const d = metres({ lat: far.lat / 1e7, lon: far.lon / 1e7 }, h)
  const small = [[100, -100], [100, 100], [-100, 100], [-100, -100]].map(([n, e], k) => item(k, V, Frame.GLOBAL_INT, ...at(n, e), 0, [4, 0, 0, 0], TYPE.FENCE))
  const breachText = gcs.next('STATUSTEXT', (t) => t.text.startsWith('failsafe geofence'), 5000)
  const unhealthy = gcs.next('SYS_STATUS', (s) => (s.onboardControlSensorsPresent & GEOFENCE) !== 0 && (s.onboardControlSensorsHealth & GEOFENCE) === 0, 5000)
  check((await upload(small, TYPE.FENCE)).type === R.ACCEPTED, `a 200-m square about home uploaded with the aircraft ${d.toFixed(0)} m away`)
  const t0 = performance.now()
  const said = await breachText
  const tSaid = performance.now() - t0
  check(tSaid < 1000 && said.severity === common.MavSeverity.WARNING, `the breach reported in ${tSaid.toFixed(0)} ms: "${said.text}"`)
  await unhealthy
  check(performance.now() - t0 < 2000, 'SYS_STATUS: the geofence unhealthy while breached')
  listed = await download(TYPE.MISSION)
  check(listed.length === 1 && listed[0].command === Cmd.NAV_RETURN_TO_LAUNCH,
  `acted on: the aircraft returns home (the rally points lie outside the new fence) (${listed.map((i) => i.command).join(' ')})`)

  // ---- clear ----
  for (const t of [TYPE.FENCE, TYPE.RALLY]) {
    const ack = gcs.next('MISSION_ACK', (a) => a.missionType === t, 3000)
    gcs.send(Object.assign(target(new common.MissionClearAll()), { missionType: t }))
    check((await ack).type === R.ACCEPTED && (await download(t)).length === 0, `MISSION_CLEAR_ALL of mission type ${t}: accepted, the list empty`)
  }
  check(gcs.crcErrors === 0, `node-mavlink found ${gcs.crcErrors} CRC errors in tern's frames`)
} catch (e) {
  failures.push(e.message)
  console.log(`FAIL ${e.message}`)
}

await flight.finish(check)
process.exit(report(failures, gcs))
