// A Foxglove WebSocket client built from Foxglove's own npm packages (independent of sweetspot's Rust code):
// connects to URL, subscribes to the given topics, decodes every message with the ros2msg schema the
// server advertises (@foxglove/rosmsg + @foxglove/rosmsg2-serialization; a `json` channel as JSON) and prints
// one JSON line per message:
// {"topic": ..., "message": {...}} (uint64 as numbers when exact, else strings; NaN as null; a time's
// nanoseconds as `nsec`, Foxglove's name for builtin_interfaces/Time's `nanosec`).
//
//   node foxglove_client.mjs URL COUNT TOPIC...   exits after COUNT messages on the first TOPIC
//   node foxglove_client.mjs URL stall TOPIC...   subscribes, prints {"subscribed":...}, then stops reading
//   node foxglove_client.mjs URL play:SEEK_NS:SPEED TOPIC...
//                                                 (a server with playback controls, `bag play --foxglove`)
//                                                 subscribes, waits 500 ms, asks to play from SEEK_NS at SPEED,
//                                                 prints {"requested": ...} as it asks, then every message
//                                                 with its log time and every playback
//                                                 state ({"playback": ...}), and exits 500 ms after playback
//                                                 has ended
//
// @foxglove/ws-protocol 0.8 knows neither the playbackControlRequest (client binary opcode 3) nor the
// playbackState (server binary opcode 5) of the protocol's v1 spec, so this client writes and reads those two
// binary messages itself (layouts: ws-protocol's docs/spec.md).
import wsProtocol from "@foxglove/ws-protocol";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import WebSocket from "ws";

const { FoxgloveClient } = wsProtocol;

const [url, countArg, ...topics] = process.argv.slice(2);
if (!url || !countArg || topics.length === 0) {
  console.error("usage: foxglove_client.mjs URL COUNT|stall TOPIC...");
  process.exit(2);
}
const stall = countArg === "stall";
const play = countArg.startsWith("play:") ? countArg.split(":").slice(1) : undefined;
const want = stall || play ? 0 : Number(countArg);
// The foxglove SDK's server (0.30) names the v1 protocol "foxglove.sdk.v1" and no longer accepts the older
// name "foxglove.websocket.v1" that this client library still offers; the v1 messages are the same.
const ws = new WebSocket(url, ["foxglove.sdk.v1", FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
const playbackStatus = ["playing", "paused", "buffering", "ended"];
const handled = ws.onmessage;
ws.onmessage = (event) => {
  const bytes = event.data instanceof ArrayBuffer ? new Uint8Array(event.data) : undefined;
  if (bytes && bytes[0] === 5) {
    // playbackState: status u8, current_time u64, speed f32, did_seek u8, request_id (u32 length + UTF-8).
    const view = new DataView(bytes.buffer, bytes.byteOffset + 1);
    const idLength = view.getUint32(14, true);
    const state = {
      status: playbackStatus[view.getUint8(0)],
      current_time: view.getBigUint64(1, true).toString(),
      speed: view.getFloat32(9, true),
      did_seek: view.getUint8(13) !== 0,
      request_id: new TextDecoder().decode(bytes.subarray(19, 19 + idLength)),
    };
    const line = JSON.stringify({ playback: state }) + "\n";
    if (state.status === "ended") {
      // The SDK sends states on its control queue and messages on its data queue, so the last messages may
      // arrive after "ended": keep reading a moment before leaving.
      process.stdout.write(line, () => setTimeout(() => process.exit(0), 500));
    } else {
      process.stdout.write(line);
    }
    return;
  }
  handled(event);
};

function requestPlayback(seekNs, speed) {
  // playbackControlRequest: opcode 3, command u8 (0 play), speed f32, had_seek u8, seek_time u64, request_id.
  const id = new TextEncoder().encode("seek-1");
  const buffer = new ArrayBuffer(1 + 1 + 4 + 1 + 8 + 4 + id.length);
  const view = new DataView(buffer);
  view.setUint8(0, 3);
  view.setUint8(1, 0);
  view.setFloat32(2, speed, true);
  view.setUint8(6, 1);
  view.setBigUint64(7, BigInt(seekNs), true);
  view.setUint32(15, id.length, true);
  new Uint8Array(buffer, 19).set(id);
  // Said before it is sent, so every message printed after this line came after play was pressed.
  process.stdout.write(JSON.stringify({ requested: { seek: String(seekNs), speed } }) + "\n");
  ws.send(buffer);
}
const readers = new Map(); // subscription id -> { topic, reader }
const pending = new Set(topics);
let counted = 0;

const replacer = (_key, value) => {
  if (typeof value === "bigint") return Number.isSafeInteger(Number(value)) ? Number(value) : value.toString();
  if (ArrayBuffer.isView(value)) return Array.from(value); // float64[] decodes as a Float64Array
  return value;
};

client.on("error", (e) => {
  console.error(`client error: ${e}`);
  process.exit(1);
});
client.on("close", () => {
  if (!stall) {
    console.error(`closed after ${counted} of ${want} messages`);
    process.exit(1);
  }
});
const wanted = new Map(); // topic -> channel, until every wanted topic is advertised
client.on("advertise", (channels) => {
  if (pending.size === 0) return;
  for (const ch of channels) {
    if (pending.delete(ch.topic)) wanted.set(ch.topic, ch);
  }
  // In the order given, once all are advertised: the server handles one client's subscriptions in order, so
  // the first message on the last topic (a latched one) tells the caller every earlier subscription holds.
  for (const topic of pending.size === 0 ? topics : []) {
    const ch = wanted.get(topic);
    let reader;
    if (ch.encoding === "cdr" && ch.schemaEncoding === "ros2msg") {
      reader = new MessageReader(parse(ch.schema, { ros2: true }));
    } else if (ch.encoding === "json" && ch.schemaEncoding === "jsonschema") {
      // Foxglove's own schemas in JSON (the scenes' frame): the message is the JSON text.
      reader = { readMessage: (bytes) => JSON.parse(new TextDecoder().decode(bytes)) };
    } else {
      console.error(`${ch.topic}: encoding ${ch.encoding}, schema ${ch.schemaEncoding}`);
      process.exit(1);
    }
    const id = client.subscribe(ch.id);
    readers.set(id, { topic: ch.topic, schemaName: ch.schemaName, reader });
  }
  if (pending.size === 0) {
    console.log(JSON.stringify({ subscribed: topics }));
    if (stall) {
      // Stop reading: the socket's buffers and then the server's queue for this client fill up.
      ws._socket.pause();
    }
    if (play) {
      setTimeout(() => requestPlayback(play[0], Number(play[1])), 500);
    }
  }
});
client.on("message", ({ subscriptionId, timestamp, data }) => {
  const sub = readers.get(subscriptionId);
  if (!sub) return;
  const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  const message = sub.reader.readMessage(bytes);
  const logTime = timestamp.toString();
  const line = JSON.stringify({ topic: sub.topic, type: sub.schemaName, log_time: logTime, message }, replacer) + "\n";
  if (sub.topic === topics[0] && ++counted === want) {
    readers.clear();
    // Exit once stdout (a pipe, written asynchronously) has taken the last line.
    process.stdout.write(line, () => process.exit(0));
  } else if (counted < want || stall || play) {
    process.stdout.write(line);
  }
});
