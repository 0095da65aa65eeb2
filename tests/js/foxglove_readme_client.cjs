// `@foxglove/ws-protocol`'s FoxgloveClient used exactly as its README's client template shows (the classic
// subprotocol `foxglove.websocket.v1` only, no playback controls), subscribing to every `cdr` channel instead
// of every `json` one. Prints one JSON line per event and, SECONDS after connecting, closes the connection:
//   {"open": "<negotiated subprotocol>"}          when the handshake is done
//   {"message": TOPIC, "log_time": "<ns>"}        per message
//   {"error": "..."}                              per client error (e.g. "Unrecognized server opcode: 5")
//   {"close": CODE}                               the close code the client saw: its Close carries no code,
//                                                 so an answered one echoes none (1005, RFC 6455 §7.1.5);
//                                                 1006 when the connection just ends), then exits
//
//   node foxglove_readme_client.cjs URL SECONDS
const { FoxgloveClient } = require("@foxglove/ws-protocol");
const { WebSocket } = require("ws");

const [url, seconds] = process.argv.slice(2);
const say = (event) => process.stdout.write(JSON.stringify(event) + "\n");

async function main() {
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const topics = new Map();
  client.on("open", () => say({ open: ws.protocol }));
  client.on("error", (error) => say({ error: String(error && error.message ? error.message : error) }));
  client.on("advertise", (channels) => {
    for (const channel of channels) {
      if (channel.encoding !== "cdr") {
        console.warn(`Unsupported encoding ${channel.encoding}`);
        continue;
      }
      const subId = client.subscribe(channel.id);
      topics.set(subId, channel.topic);
    }
  });
  client.on("message", ({ subscriptionId, timestamp }) => {
    say({ message: topics.get(subscriptionId), log_time: timestamp.toString() });
  });
  client.on("close", (event) => {
    process.stdout.write(JSON.stringify({ close: event.code }) + "\n", () => process.exit(0));
  });
  setTimeout(() => client.close(), Number(seconds) * 1000);
  // Bounded: the test never waits for ever on a close that does not come.
  setTimeout(() => {
    say({ close: "none within 5 s of closing" });
    process.exit(1);
  }, Number(seconds) * 1000 + 5000);
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
