// A ground station's end of a MAVLink link for tern's tests: a UDP socket on loopback and
// node-mavlink's reader (its own splitter, CRCs and message classes), as QGroundControl would hold.
//
//   const gcs = await openGcs()          // bound to a free port: gcs.port
//   await gcs.next('HEARTBEAT', (d, h) => ..., ms)   // the next such message (rejects after ms); h: its
//                                        // frame's header (h.sysid: the vehicle's system id)
//   gcs.send(msg)                        // to the address the vehicle's packets came from
//   const stop = gcs.listen('MISSION_REQUEST_INT', (d, h) => ...)   // every such message until stop()
//   gcs.texts                            // every STATUSTEXT so far; gcs.crcErrors: frames node-mavlink refused
import dgram from 'node:dgram'
import { Readable } from 'node:stream'
import { MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, standard, common } from 'node-mavlink'

export const REGISTRY = { ...minimal.REGISTRY, ...standard.REGISTRY, ...common.REGISTRY }

export async function openGcs() {
  const sock = dgram.createSocket('udp4')
  await new Promise((resolve) => sock.bind(0, '127.0.0.1', resolve))
  const input = new Readable({ read() {} })
  const gcs = { port: sock.address().port, vehicle: null, texts: [], crcErrors: 0, seen: {}, waiters: [], listeners: [] }
  const reader = input
    .pipe(new MavLinkPacketSplitter({}, { onCrcError: () => gcs.crcErrors++ }))
    .pipe(new MavLinkPacketParser())
  sock.on('message', (buf, rinfo) => {
    if (!gcs.vehicle) gcs.vehicle = { address: rinfo.address, port: rinfo.port }
    input.push(buf)
  })
  reader.on('data', (packet) => {
    const clazz = REGISTRY[packet.header.msgid]
    if (!clazz) return
    const data = packet.protocol.data(packet.payload, clazz)
    const name = clazz.MSG_NAME
    gcs.seen[name] = (gcs.seen[name] || 0) + 1
    if (name === 'STATUSTEXT') gcs.texts.push(data.text)
    for (const l of [...gcs.listeners]) if (l.name === name) l.fn(data, packet.header)
    for (const w of [...gcs.waiters]) {
      if (w.name === name && w.match(data, packet.header)) {
        gcs.waiters.splice(gcs.waiters.indexOf(w), 1)
        clearTimeout(w.timer)
        w.resolve(data)
      }
    }
  })
  gcs.next = (name, match = () => true, ms = 10000) =>
    new Promise((resolve, reject) => {
      const w = { name, match, resolve }
      w.timer = setTimeout(() => {
        gcs.waiters.splice(gcs.waiters.indexOf(w), 1)
        reject(new Error(`no ${name} within ${ms} ms`))
      }, ms)
      gcs.waiters.push(w)
    })
  gcs.listen = (name, fn) => {
    const l = { name, fn }
    gcs.listeners.push(l)
    return () => gcs.listeners.splice(gcs.listeners.indexOf(l), 1)
  }
  const protocol = new MavLinkProtocolV2(255, 190) // a GCS: system 255, MAV_COMP_ID_MISSIONPLANNER
  let seq = 0
  gcs.send = (msg) => sock.send(protocol.serialize(msg, seq++ & 255), gcs.vehicle.port, gcs.vehicle.address)
  gcs.close = () => sock.close()
  return gcs
}
