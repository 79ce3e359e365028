// tern's parameter metadata as QGroundControl fetches it (core/apps/mavlink/component_metadata.hpp,
// mavlink_ftp.hpp; docs/ground-station.md, "Parameter metadata") against node-mavlink playing the
// ground station:
//
//   node test_gcs_metadata.mjs TERN MISSION WORK_DIR
//
// It flies MISSION with `tern fly --realtime --gcs` and:
//   - asks COMPONENT_METADATA (MAV_CMD_REQUEST_MESSAGE 397) and COMPONENT_INFORMATION (395, the
//     older QGroundControl's): both name the general metadata file by an mftp:// URI;
//   - downloads it over MAVLink FTP (OpenFileRO, BurstReadFile, TerminateSession), reads the
//     parameter metadata URI from it, and downloads that (OpenFileRO, ReadFile chunk by chunk);
//   - checks that every parameter of PARAM_REQUEST_LIST is described under its id, with its type,
//     a description and its group, and that the ranges hold the values the vehicle reports;
//   - hostile FTP: a file that does not exist (NAK FileNotFound), a write (NAK UnknownCommand),
//     a read on a closed session (NAK InvalidSession).
// Exit 0 when all hold; 1 with one line per failure.
import { common, MavLinkData, MavLinkPacketField, MSG_ID_MAGIC_NUMBER } from 'node-mavlink'
import { openGcs, REGISTRY } from './gcs_client.mjs'
import { flyWithGcs, missionClient, report, reporter } from './gcs_session.mjs'

// COMPONENT_METADATA (397) is not in node-mavlink's common set: its layout from common.xml
// (tests/mavlink/crc_extra_common.txt: CRC_EXTRA 182, 108 bytes)
class ComponentMetadata extends MavLinkData {
  constructor() {
    super()
    this.timeBootMs = 0
    this.fileCrc = 0
    this.uri = ''
  }
}
ComponentMetadata.MSG_ID = 397
ComponentMetadata.MSG_NAME = 'COMPONENT_METADATA'
ComponentMetadata.PAYLOAD_LENGTH = 108
ComponentMetadata.MAGIC_NUMBER = 182
ComponentMetadata.FIELDS = [
  new MavLinkPacketField('time_boot_ms', 'timeBootMs', 0, false, 4, 'uint32_t', 'ms'),
  new MavLinkPacketField('file_crc', 'fileCrc', 4, false, 4, 'uint32_t', ''),
  new MavLinkPacketField('uri', 'uri', 8, false, 1, 'char[]', '', 100),
]
REGISTRY[397] = ComponentMetadata
MSG_ID_MAGIC_NUMBER[397] = ComponentMetadata.MAGIC_NUMBER // the splitter checks each frame's CRC with it

const [tern, mission, work] = process.argv.slice(2)
if (!tern || !mission || !work) {
  console.error('usage: node test_gcs_metadata.mjs TERN MISSION WORK_DIR')
  process.exit(2)
}
const { failures, check } = reporter()
const Cmd = common.MavCmd
const OP = { TERMINATE: 1, OPEN_RO: 4, READ: 5, WRITE: 7, BURST: 15, ACK: 128, NAK: 129 }
const ERR = { EOF: 6, UNKNOWN: 7, INVALID_SESSION: 4, NOT_FOUND: 10 }

const gcs = await openGcs()
const { target, command } = missionClient(gcs)

// ---- a MAVLink FTP client (https://mavlink.io/en/services/ftp.html) ----
let seq = 0
const header = (p) => ({ seq: p[0] | (p[1] << 8), session: p[2], opcode: p[3], size: p[4], req: p[5], burstComplete: p[6], offset: p[8] | (p[9] << 8) | (p[10] << 16) | (p[11] << 24), data: p.slice(12, 12 + p[4]) })
function ftpRequest(opcode, { session = 0, offset = 0, data = [], size = data.length } = {}) {
  const p = new Array(251).fill(0)
  seq = (seq + 1) & 0xffff
  p[0] = seq & 0xff; p[1] = seq >> 8; p[2] = session; p[3] = opcode; p[4] = size
  for (let k = 0; k < 4; k++) p[8 + k] = (offset >>> (8 * k)) & 0xff
  data.forEach((b, k) => { p[12 + k] = b })
  return Object.assign(target(new common.FileTransferProtocol()), { targetNetwork: 0, payload: p })
}
async function ftp(opcode, opts) {
  const want = (seq + 2) & 0xffff
  const answer = gcs.next('FILE_TRANSFER_PROTOCOL', (m) => header(m.payload).seq === want, 3000)
  gcs.send(ftpRequest(opcode, opts))
  return header((await answer).payload)
}
const bytes = (s) => [...Buffer.from(s)]
async function download(file, burst) {
  const open = await ftp(OP.OPEN_RO, { data: bytes(file) })
  if (open.opcode !== OP.ACK) return { error: open.data[0] }
  const size = open.data[0] | (open.data[1] << 8) | (open.data[2] << 16) | (open.data[3] << 24)
  const buf = Buffer.alloc(size)
  let got = 0
  if (burst) {
    const chunks = []
    const stop = gcs.listen('FILE_TRANSFER_PROTOCOL', (m) => chunks.push(header(m.payload)))
    const done = gcs.next('FILE_TRANSFER_PROTOCOL', (m) => header(m.payload).burstComplete === 1, 5000)
    gcs.send(ftpRequest(OP.BURST, { session: open.session }))
    await done
    stop()
    for (const c of chunks) if (c.opcode === OP.ACK && c.req === OP.BURST) { Buffer.from(c.data).copy(buf, c.offset); got += c.size }
  } else {
    for (;;) {
      const r = await ftp(OP.READ, { session: open.session, offset: got, size: 239 })
      if (r.opcode === OP.NAK) break
      Buffer.from(r.data).copy(buf, r.offset)
      got += r.size
    }
  }
  const closed = await ftp(OP.TERMINATE, { session: open.session })
  return { text: buf.toString('utf8'), size, got, session: open.session, closed: closed.opcode === OP.ACK }
}

const flight = flyWithGcs(tern, mission, work, gcs, 60)

try {
  await gcs.next('HEARTBEAT', () => true, 20000)
  const metaP = gcs.next('COMPONENT_METADATA', () => true, 3000)
  check(await command(Cmd.REQUEST_MESSAGE, [397]) === common.MavResult.ACCEPTED, 'REQUEST_MESSAGE COMPONENT_METADATA accepted')
  const uri = (await metaP).uri
  check(uri.startsWith('mftp://'), `COMPONENT_METADATA names the general metadata by an mftp:// URI (${uri})`)
  const infoP = gcs.next('COMPONENT_INFORMATION', () => true, 3000)
  check(await command(Cmd.REQUEST_MESSAGE, [395]) === common.MavResult.ACCEPTED, 'REQUEST_MESSAGE COMPONENT_INFORMATION accepted')
  check((await infoP).generalMetadataUri === uri, 'COMPONENT_INFORMATION names the same file')

  const general = await download(uri.slice('mftp://'.length), true)
  check(general.got === general.size && general.closed, `the general metadata downloaded by burst: ${general.got} of ${general.size} bytes, session closed`)
  const types = JSON.parse(general.text).metadataTypes
  const paramUri = types.find((t) => t.type === 1)?.uri ?? ''
  check(paramUri.startsWith('mftp://'), `it names the parameter metadata (${paramUri})`)
  const t0 = performance.now()
  const params = await download(paramUri.slice('mftp://'.length), false)
  check(params.got === params.size, `the parameter metadata downloaded by ReadFile: ${params.size} bytes in ${(performance.now() - t0).toFixed(0)} ms`)
  const described = new Map(JSON.parse(params.text).parameters.map((p) => [p.name, p]))

  // every parameter the vehicle lists
  const listed = new Map()
  const all = new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`PARAM_VALUE: ${listed.size} parameters within 10 s`)), 10000)
    const stop = gcs.listen('PARAM_VALUE', (v) => {
      listed.set(v.paramId, v)
      if (listed.size === v.paramCount) { clearTimeout(timer); stop(); resolve() }
    })
  })
  gcs.send(target(new common.ParamRequestList()))
  await all
  const missing = [...listed.keys()].filter((id) => !described.has(id))
  check(missing.length === 0 && described.size === listed.size, `all ${listed.size} parameters described (${described.size} entries; missing: ${missing.slice(0, 5).join(', ')})`)
  const bare = [...described.values()].filter((p) => !p.shortDesc || !p.group || !['Float', 'Int32'].includes(p.type))
  check(bare.length === 0, `each with a description, a group and a type (${bare.slice(0, 5).map((p) => p.name).join(', ')})`)
  const outside = [...listed.values()].filter((v) => { const p = described.get(v.paramId); return p && ((p.min !== undefined && v.paramValue < p.min - 1e-6 * Math.abs(p.min)) || (p.max !== undefined && v.paramValue > p.max + 1e-6 * Math.abs(p.max))) })
  check(outside.length === 0, `every value within its described range (${outside.slice(0, 3).map((v) => `${v.paramId}=${v.paramValue}`).join(', ')})`)

  // ---- hostile FTP ----
  const nf = await ftp(OP.OPEN_RO, { data: bytes('etc/passwd') })
  check(nf.opcode === OP.NAK && nf.data[0] === ERR.NOT_FOUND, 'OpenFileRO of another file: NAK FileNotFound')
  const wr = await ftp(OP.WRITE, { data: bytes('x') })
  check(wr.opcode === OP.NAK && wr.data[0] === ERR.UNKNOWN, 'a write: NAK UnknownCommand (read-only)')
  const stale = await ftp(OP.READ, { session: params.session, size: 10 })
  check(stale.opcode === OP.NAK && stale.data[0] === ERR.INVALID_SESSION, 'a read on a closed session: NAK InvalidSession')
  check(gcs.crcErrors === 0, `node-mavlink found ${gcs.crcErrors} CRC errors in tern's frames`)
} catch (e) {
  failures.push(e.message)
  console.log(`FAIL ${e.message}`)
}

await flight.finish(check)
process.exit(report(failures, gcs))
