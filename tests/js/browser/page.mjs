// The page side of foxglove_browser.mjs, bundled for the browser by esbuild: Foxglove's own client
// (@foxglove/ws-protocol's FoxgloveClient) on the browser's WebSocket, offering only the classic subprotocol
// `foxglove.websocket.v1` as the package's README shows, and Foxglove's ROS 2 decoder (@foxglove/rosmsg +
// @foxglove/rosmsg2-serialization; a `json` channel as JSON). Everything it sees goes to `window.report`
// (which the Node.js side prints as one JSON line per event):
//   {"open": "<negotiated subprotocol>"}
//   {"advertised": [topic, ...]}                  per advertisement
//   {"subscribed": [topic, ...]}                  once every wanted topic is subscribed
//   {"topic", "type", "message"}                  per message, decoded
//   {"error": "..."}                              per client error (e.g. "Unrecognized server opcode …")
//   {"close": code, "clean": wasClean}            the CloseEvent the browser reports
import { FoxgloveClient } from "@foxglove/ws-protocol";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";

const replacer = (_key, value) => {
  if (typeof value === "bigint") return Number.isSafeInteger(Number(value)) ? Number(value) : value.toString();
  if (ArrayBuffer.isView(value)) return Array.from(value);
  return value;
};
const report = (event) => window.report(JSON.stringify(event, replacer));

// url: the server; topics: those to subscribe to (empty: every channel); count: close after this many
// messages (on topics[0], or on any topic when topics is empty); linger: ms to keep reading after that.
window.sweetspotRun = ({ url, topics, count, linger }) => {
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const readers = new Map(); // subscription id -> { topic, type, reader }
  const pending = new Set(topics);
  let counted = 0;
  let announced = false;
  let closing = false;
  const close = () => {
    if (closing) return;
    closing = true;
    setTimeout(() => client.close(), linger);
  };
  client.on("open", () => report({ open: ws.protocol }));
  client.on("error", (error) => report({ error: String(error && error.message ? error.message : error) }));
  client.on("close", (event) => report({ close: event.code, clean: event.wasClean }));
  const subscribe = (ch) => {
    let reader;
    if (ch.encoding === "cdr" && ch.schemaEncoding === "ros2msg") {
      reader = new MessageReader(parse(ch.schema, { ros2: true }));
    } else if (ch.encoding === "json") {
      reader = { readMessage: (bytes) => JSON.parse(new TextDecoder().decode(bytes)) };
    } else {
      report({ error: `${ch.topic}: encoding ${ch.encoding}, schema ${ch.schemaEncoding}` });
      return;
    }
    readers.set(client.subscribe(ch.id), { topic: ch.topic, type: ch.schemaName, reader });
  };
  const wanted = new Map(); // topic -> channel, until every wanted topic is advertised
  client.on("advertise", (channels) => {
    report({ advertised: channels.map((ch) => ch.topic) });
    if (topics.length === 0) {
      channels.forEach(subscribe);
      return;
    }
    for (const ch of channels) {
      if (pending.delete(ch.topic)) wanted.set(ch.topic, ch);
    }
    if (pending.size === 0 && !announced) {
      // In the order given: the server handles one client's subscriptions in order, so the first message on
      // the last topic (a latched one) tells the caller that every earlier subscription is in effect.
      for (const topic of topics) subscribe(wanted.get(topic));
      announced = true;
      report({ subscribed: topics });
    }
  });
  client.on("message", ({ subscriptionId, data }) => {
    const sub = readers.get(subscriptionId);
    if (!sub) return;
    let message;
    try {
      message = sub.reader.readMessage(new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
    } catch (e) {
      report({ error: `${sub.topic}: ${e}` });
      return;
    }
    report({ topic: sub.topic, type: sub.type, message });
    if ((topics.length === 0 || sub.topic === topics[0]) && ++counted === count) close();
  });
  return { close };
};
