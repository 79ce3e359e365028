// tern's mission protocol and commands over MAVLink (core/apps/mavlink/mission_protocol.hpp,
// gcs_commands.hpp, docs/ground-station.md) against node-mavlink playing the ground station, as
// QGroundControl's Plan view and "Fly here" do:
//
//   node test_gcs_mission.mjs TERN MISSION WORK_DIR
//
// It flies MISSION with `tern fly --realtime --gcs` and, waiting on messages (no sleeping):
//   - AUTOPILOT_VERSION (MAV_CMD_REQUEST_MESSAGE) with MISSION_INT, COMMAND_INT, PARAM_FLOAT, MAVLINK2;
//     HOME_POSITION on request;
//   - downloads the configured mission before any upload (the planner's list as items);
//   - hostile mission traffic: a count of 65535 (NO_SPACE), a waypoint in a FENCE upload and a
//     download of mission type 7 (UNSUPPORTED, the ACK carrying their mission type), items out of
//     order (the expected one asked again), an upload abandoned half way (re-requested, then
//     OPERATION_CANCELLED) leave the mission as it was; bad items (a DO_JUMP past the end, a LOCAL_NED frame) are
//     refused with their MAV_MISSION_RESULT and a STATUSTEXT naming the item;
//   - uploads 10 items and reads them back identical; MISSION_SET_CURRENT keeps them;
//   - an arm in flight is DENIED with a STATUSTEXT; DO_REPOSITION to a point 300 m away: the
//     aircraft (GLOBAL_POSITION_INT) goes there and orbits it; NAV_RETURN_TO_LAUNCH lists a return;
//     MISSION_START flies the upload again (with NaN items it is DENIED and changes nothing); an unknown command is UNSUPPORTED, SET_MESSAGE_INTERVAL DENIED;
//   - a 100-item mission (50 waypoints, 50 speed changes) uploaded and read back: prints the time
//     ("bench: ..."; the target, under 1 s, is the bench's, not asserted here); MISSION_CLEAR_ALL.
// Exit 0 when all hold; 1 with one line per failure.
import { common } from 'node-mavlink'
import { openGcs } from './gcs_client.mjs'
import { flyWithGcs, missionClient, report, reporter } from './gcs_session.mjs'

const [tern, mission, work] = process.argv.slice(2)
if (!tern || !mission || !work) {
  console.error('usage: node test_gcs_mission.mjs TERN MISSION WORK_DIR')
  process.exit(2)
}
const { failures, check } = reporter()
const R = common.MavMissionResult
const Cmd = common.MavCmd
const Frame = common.MavFrame
const M = 111320 // m per degree of latitude (a GCS's flat-earth placement: tern converts with GeographicLib)

const gcs = await openGcs()
const { target, item, upload, download, differences, command } = missionClient(gcs)
/** Metres between two lat/lon (deg) points, flat-earth (enough within a km). */
const metres = (a, b) => Math.hypot((a.lat - b.lat) * M, (a.lon - b.lon) * M * Math.cos((a.lat * Math.PI) / 180))

// ---- fly ----
const flight = flyWithGcs(tern, mission, work, gcs, 150)

try {
  await gcs.next('HEARTBEAT', (d) => (d.baseMode & 128) !== 0, 20000) // armed: flying
  // ---- what QGroundControl asks at connect ----
  const versionP = gcs.next('AUTOPILOT_VERSION', () => true, 3000)
  check(await command(Cmd.REQUEST_MESSAGE, [148]) === common.MavResult.ACCEPTED, 'REQUEST_MESSAGE AUTOPILOT_VERSION accepted')
  const caps = BigInt((await versionP).capabilities)
  const need = 4n | 8n | 2n | 8192n // MISSION_INT, COMMAND_INT, PARAM_FLOAT, MAVLINK2
  check((caps & need) === need, `AUTOPILOT_VERSION capabilities ${caps} hold MISSION_INT, COMMAND_INT, PARAM_FLOAT, MAVLINK2`)
  const homeP = gcs.next('HOME_POSITION', () => true, 3000)
  check(await command(Cmd.REQUEST_MESSAGE, [242]) === common.MavResult.ACCEPTED, 'REQUEST_MESSAGE HOME_POSITION accepted')
  const home = await homeP
  const h = { lat: home.latitude / 1e7, lon: home.longitude / 1e7 }
  const at = (north, east) => [h.lat + north / M, h.lon + east / (M * Math.cos((h.lat * Math.PI) / 180))]

  // ---- the configured mission, before any upload ----
  const configured = await download()
  check(configured.length === 5 && configured[0].command === Cmd.DO_CHANGE_SPEED && configured[0].param2 === 17 &&
    configured.slice(1).every((i) => i.command === Cmd.NAV_WAYPOINT && Math.abs(i.z - 70) < 0.5),
  `the configured mission downloads as DO_CHANGE_SPEED 17 and 4 NAV_WAYPOINTs 70 m up (${configured.map((i) => i.command).join(' ')})`)
  const wp0 = configured[1]
  const [lat0, lon0] = at(400, -250)
  check(metres({ lat: wp0.x / 1e7, lon: wp0.y / 1e7 }, { lat: lat0, lon: lon0 }) < 1, 'its first waypoint is NED (400, -250) m from home')

  // ---- hostile mission traffic ----
  const huge = gcs.next('MISSION_ACK', () => true, 3000)
  gcs.send(Object.assign(target(new common.MissionCount()), { count: 65535, missionType: 0 }))
  check((await huge).type === R.NO_SPACE, 'MISSION_COUNT 65535 answered MAV_MISSION_NO_SPACE')
  const fence = await upload([item(0, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, h.lat, h.lon, 50, [0, 0, 0, 0], 1)], 1)
  check(fence.type === R.UNSUPPORTED, `a NAV_WAYPOINT in a FENCE upload answered MAV_MISSION_UNSUPPORTED (${fence.type})`)
  check(fence.missionType === 1, `... in a MISSION_ACK whose mission_type is FENCE, as a planner matches it (${fence.missionType})`)
  const unknown = gcs.next('MISSION_ACK', () => true, 3000)
  gcs.send(Object.assign(target(new common.MissionRequestList()), { missionType: 7 }))
  const r7 = await unknown
  check(r7.type === R.UNSUPPORTED && r7.missionType === 7, `a download of mission type 7 answered UNSUPPORTED with that mission_type (${r7.type}, ${r7.missionType})`)
  // out of order: item 2 first; the vehicle asks for 0 again
  const again = gcs.next('MISSION_REQUEST_INT', (d) => d.seq === 0, 2000)
  const first = gcs.next('MISSION_REQUEST_INT', (d) => d.seq === 0, 2000)
  gcs.send(Object.assign(target(new common.MissionCount()), { count: 3, missionType: 0 }))
  await first
  gcs.send(item(2, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(100, 0), 60))
  check((await again).seq === 0, 'an item out of order: item 0 requested again')
  // abandoned after two items: re-requested, then given up
  const asked = []
  const stop = gcs.listen('MISSION_REQUEST_INT', (r) => asked.push(r.seq))
  const part = [item(0, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(100, 0), 60), item(1, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(0, 100), 60)]
  const given = gcs.next('MISSION_ACK', () => true, 5000)
  const cancelled = gcs.next('STATUSTEXT', (d) => d.text.includes('given up'), 5000)
  const r1 = gcs.next('MISSION_REQUEST_INT', (d) => d.seq === 1, 2000)
  gcs.send(Object.assign(target(new common.MissionCount()), { count: 5, missionType: 0 })) // restarts the out-of-order one
  gcs.send(part[0])
  await r1
  gcs.send(part[1])
  const g = await given
  stop()
  check(g.type === R.OPERATION_CANCELLED && asked.filter((s) => s === 2).length >= 3,
    `an upload abandoned at item 2: asked ${asked.filter((s) => s === 2).length} times, then MAV_MISSION_OPERATION_CANCELLED (${g.type})`)
  check((await cancelled).severity === common.MavSeverity.WARNING, 'a STATUSTEXT says the upload was given up')
  check(differences(configured, await download()).length === 0, 'the mission is unchanged after the hostile traffic')

  // ---- bad items ----
  const jumpText = gcs.next('STATUSTEXT', (d) => d.text.startsWith('mission item 2 '), 3000)
  const jump = await upload([item(0, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(100, 0), 60),
    item(1, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(0, 100), 60), item(2, Cmd.DO_JUMP, Frame.MISSION, 0, 0, 0, [9, 3, 0, 0])])
  check(jump.type === R.INVALID_PARAM1, `a DO_JUMP past the mission's end refused: MAV_MISSION_INVALID_PARAM1 (${jump.type})`)
  check((await jumpText).text.includes('DO_JUMP'), 'a STATUSTEXT names item 2 and its command')
  const local = await upload([item(0, Cmd.NAV_WAYPOINT, Frame.LOCAL_NED, 0, 0, -60)])
  check(local.type === R.UNSUPPORTED_FRAME, `a LOCAL_NED item refused: MAV_MISSION_UNSUPPORTED_FRAME (${local.type})`)

  // ---- a plan of 10 items, uploaded and read back ----
  const plan = [
    item(0, Cmd.NAV_TAKEOFF, Frame.GLOBAL_RELATIVE_ALT_INT, 0, 0, 60, [15, 0, 0, NaN]),
    item(1, Cmd.DO_CHANGE_SPEED, Frame.MISSION, 0, 0, 0, [0, 18, -1, 0]),
    item(2, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(350, -250), 80),
    item(3, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT, ...at(-350, -250), 80),
    item(4, Cmd.NAV_LOITER_TURNS, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(-350, 250), 80, [1, 0, -90, NaN]),
    item(5, Cmd.NAV_WAYPOINT, Frame.GLOBAL_INT, ...at(350, 250), (home.altitude / 1000) + 90),
    item(6, Cmd.NAV_LOITER_TIME, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(0, 400), 90, [20, 0, 100, NaN]),
    item(7, Cmd.DO_CHANGE_SPEED, Frame.MISSION, 0, 0, 0, [0, 16, -1, 0]),
    item(8, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(-500, -600), 60),
    item(9, Cmd.NAV_LOITER_UNLIM, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(0, 0), 70, [0, 0, 120, NaN]),
  ]
  let t0 = performance.now()
  const accepted = await upload(plan)
  const back = await download()
  const tPlan = performance.now() - t0
  check(accepted.type === R.ACCEPTED, `a plan of ${plan.length} items accepted (${accepted.type}; ${JSON.stringify(gcs.texts.slice(-1))})`)
  const diff = differences(plan, back)
  check(diff.length === 0, `read back identical in ${tPlan.toFixed(0)} ms (${diff.slice(0, 3).join('; ')})`)
  const setText = gcs.texts.length
  gcs.send(Object.assign(target(new common.MissionSetCurrent()), { seq: 4 }))
  await gcs.next('HEARTBEAT', () => true, 3000)
  check(gcs.texts.slice(setText).every((t) => !t.includes('refused')), 'MISSION_SET_CURRENT 4 taken')
  check(differences(plan, await download()).length === 0, 'the plan reads back the same after MISSION_SET_CURRENT (renumbered by the planner, not by the GCS)')

  // ---- commands ----
  const armText = gcs.next('STATUSTEXT', (d) => d.text.includes('refused in flight'), 3000)
  check(await command(Cmd.COMPONENT_ARM_DISARM, [1]) === common.MavResult.DENIED, 'arm in flight: MAV_RESULT_DENIED')
  check((await armText).text.startsWith('arm refused in flight'), 'a STATUSTEXT says why')
  check(await command(Cmd.COMPONENT_ARM_DISARM, [0]) === common.MavResult.DENIED, 'disarm in flight: MAV_RESULT_DENIED')
  const now = await gcs.next('GLOBAL_POSITION_INT', () => true, 3000)
  const here = { lat: now.lat / 1e7, lon: now.lon / 1e7 }
  const goal = { lat: here.lat + 300 / M, lon: here.lon }
  const radius = 80
  check(await command(Cmd.DO_REPOSITION, [-1, 1, radius, NaN], Frame.GLOBAL_RELATIVE_ALT_INT,
    [Math.round(goal.lat * 1e7), Math.round(goal.lon * 1e7), 100]) === common.MavResult.ACCEPTED, 'DO_REPOSITION 300 m north accepted')
  t0 = performance.now()
  const arrived = await gcs.next('GLOBAL_POSITION_INT', (d) => metres({ lat: d.lat / 1e7, lon: d.lon / 1e7 }, goal) < radius + 30, 60000)
  check(arrived !== undefined, `the aircraft reached the orbit about the point in ${((performance.now() - t0) / 1000).toFixed(1)} s`)
  // one turn (2 pi 80 m at 17 m/s: 30 s) to settle on the orbit, then the distances of the next 10 s
  const ring = []
  const stopRing = gcs.listen('GLOBAL_POSITION_INT', (d) => ring.push(metres({ lat: d.lat / 1e7, lon: d.lon / 1e7 }, goal)))
  const settled = performance.now() + 15000
  while (performance.now() < settled) await gcs.next('HEARTBEAT', () => true, 3000)
  ring.length = 0
  const sampled = performance.now() + 10000
  while (performance.now() < sampled) await gcs.next('HEARTBEAT', () => true, 3000)
  stopRing()
  const lo = Math.min(...ring)
  const hi = Math.max(...ring)
  check(ring.length > 20 && lo > radius - 15 && hi < radius + 15, `it orbits the point: ${ring.length} positions ${lo.toFixed(0)}-${hi.toFixed(0)} m from it (radius ${radius})`)
  const fly = await download()
  check(fly.length === 1 && fly[0].command === Cmd.NAV_LOITER_UNLIM && Math.abs(fly[0].param3 - radius) < 1e-3,
    `the download lists the orbit flown now (${fly.map((i) => i.command).join(' ')})`)

  check(await command(Cmd.NAV_RETURN_TO_LAUNCH) === common.MavResult.ACCEPTED, 'NAV_RETURN_TO_LAUNCH accepted')
  let listed = []
  for (let k = 0; k < 20 && !(listed.length === 1 && listed[0].command === Cmd.NAV_RETURN_TO_LAUNCH); k++) {
    await gcs.next('ATTITUDE', () => true, 3000)
    listed = await download()
  }
  check(listed.length === 1 && listed[0].command === Cmd.NAV_RETURN_TO_LAUNCH, 'the download lists the return')
  check(await command(Cmd.MISSION_START, [NaN, NaN]) === common.MavResult.DENIED, 'MISSION_START with NaN items: MAV_RESULT_DENIED')
  listed = await download()
  check(listed.length === 1 && listed[0].command === Cmd.NAV_RETURN_TO_LAUNCH, 'a refused MISSION_START leaves the mission flown as it was')
  check(await command(Cmd.MISSION_START, [0, 0]) === common.MavResult.ACCEPTED, 'MISSION_START accepted')
  check(differences(plan, await download()).length === 0, 'MISSION_START flies the uploaded plan again (it reads back)')
  check(await command(183, [1, 1500]) === common.MavResult.UNSUPPORTED, 'an unknown command (DO_SET_SERVO): MAV_RESULT_UNSUPPORTED')
  check(await command(Cmd.SET_MESSAGE_INTERVAL, [33, 100000]) === common.MavResult.DENIED, 'SET_MESSAGE_INTERVAL: MAV_RESULT_DENIED (fixed rates)')
  check(await command(Cmd.NAV_LAND) === common.MavResult.DENIED, 'NAV_LAND without a land item in the mission: MAV_RESULT_DENIED')

  // ---- 100 items: the bench's figure ----
  const big = []
  for (let k = 0; k < 50; k++) {
    big.push(item(2 * k, Cmd.DO_CHANGE_SPEED, Frame.MISSION, 0, 0, 0, [0, 15 + (k % 5), -1, 0]))
    big.push(item(2 * k + 1, Cmd.NAV_WAYPOINT, Frame.GLOBAL_RELATIVE_ALT_INT, ...at(400 * Math.cos(k / 8), 400 * Math.sin(k / 8)), 80))
  }
  t0 = performance.now()
  const bigAck = await upload(big)
  const t1 = performance.now()
  const bigBack = await download()
  const t2 = performance.now()
  check(bigAck.type === R.ACCEPTED && differences(big, bigBack).length === 0,
    `a mission of 100 items uploads and reads back identical (${bigAck.type}; ${differences(big, bigBack).slice(0, 3).join('; ')})`)
  console.log(`bench: mission of 100 items over loopback: upload ${(t1 - t0).toFixed(1)} ms, read back ${(t2 - t1).toFixed(1)} ms, total ${(t2 - t0).toFixed(1)} ms`)
  const cleared = gcs.next('MISSION_ACK', () => true, 3000)
  gcs.send(Object.assign(target(new common.MissionClearAll()), { missionType: 0 }))
  check((await cleared).type === R.ACCEPTED, 'MISSION_CLEAR_ALL accepted')
  check((await download()).length === 0, 'the download after the clear lists no item')
  check(gcs.crcErrors === 0, `node-mavlink found ${gcs.crcErrors} CRC errors in tern's frames`)
} catch (e) {
  failures.push(e.message)
  console.log(`FAIL ${e.message}`)
}

await flight.finish(check)
process.exit(report(failures, gcs))
