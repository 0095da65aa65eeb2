// A Foxglove WebSocket client built from Foxglove's own npm packages (independent of sweetspot's Rust code):
// connects to URL, subscribes to the given topics, decodes every message with the ros2msg schema the
// server advertises (@foxglove/rosmsg + @foxglove/rosmsg2-serialization) and prints one JSON line per message:
// {"topic": ..., "message": {...}} (uint64 as numbers when exact, else strings; NaN as null; a time's
// nanoseconds as `nsec`, Foxglove's name for builtin_interfaces/Time's `nanosec`).
//
//   node foxglove_client.mjs URL COUNT TOPIC...   exits after COUNT messages on the first TOPIC
//   node foxglove_client.mjs URL stall TOPIC...   subscribes, prints {"subscribed":...}, then stops reading
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
const want = stall ? 0 : Number(countArg);
// The foxglove SDK's server (0.30) names the v1 protocol "foxglove.sdk.v1" and no longer accepts the older
// name "foxglove.websocket.v1" that this client library still offers; the v1 messages are the same.
const ws = new WebSocket(url, ["foxglove.sdk.v1", FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
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
client.on("advertise", (channels) => {
  for (const ch of channels) {
    if (!pending.has(ch.topic)) continue;
    if (ch.encoding !== "cdr" || ch.schemaEncoding !== "ros2msg") {
      console.error(`${ch.topic}: encoding ${ch.encoding}, schema ${ch.schemaEncoding}`);
      process.exit(1);
    }
    const reader = new MessageReader(parse(ch.schema, { ros2: true }));
    const id = client.subscribe(ch.id);
    readers.set(id, { topic: ch.topic, schemaName: ch.schemaName, reader });
    pending.delete(ch.topic);
  }
  if (pending.size === 0) {
    console.log(JSON.stringify({ subscribed: topics }));
    if (stall) {
      // Stop reading: the socket's buffers and then the server's queue for this client fill up.
      ws._socket.pause();
    }
  }
});
client.on("message", ({ subscriptionId, data }) => {
  const sub = readers.get(subscriptionId);
  if (!sub) return;
  const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  const message = sub.reader.readMessage(bytes);
  const line = JSON.stringify({ topic: sub.topic, type: sub.schemaName, message }, replacer) + "\n";
  if (sub.topic === topics[0] && ++counted === want) {
    readers.clear();
    // Exit once stdout (a pipe, written asynchronously) has taken the last line.
    process.stdout.write(line, () => process.exit(0));
  } else if (counted < want || stall) {
    process.stdout.write(line);
  }
});
