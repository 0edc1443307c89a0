// pathfarm's browser client: the coordinator's frames on a canvas (H.264 through WebCodecs
// where the browser has a decoder for it, JPEG otherwise); W A S D, mouse look (pointer lock),
// arrow keys and E sent back as inputs; an overlay with the frame rate, input-to-frame latency
// (p50 / p99), render size and samples per pixel. The messages are those of
// coordinator/http/web_protocol.h (docs/web.md, "Protocol").
'use strict';

const WALK_M_PER_S = 2.0, TURN_RAD_PER_S = 1.5, MOUSE_RAD_PER_PX = 0.0025; // as the SDL client
const INPUT_PERIOD_MS = 16, FRAME_HEADER_BYTES = 48, KEEP_SAMPLES = 300;
const CODEC_H264 = 1; // the header's codec byte (0: JPEG)
const H264_CODEC = 'avc1.64001F'; // High profile (the stream's), up to 1280x720 at 30 frames/s

const canvas = document.getElementById('frame');
const context = canvas.getContext('2d');
const overlay = document.getElementById('overlay');

// Everything a test may read (window.pathfarm), and the client's own bookkeeping.
const state = {
  connected: false, frames: 0, lastHeader: null, sequence: 0,
  sentAt: new Map(),       // input sequence -> performance.now() when sent
  latenciesMs: [],         // input -> first frame that shows it (the newest ones)
  latencyCount: 0,         // all measured so far
  arrivalsMs: [],          // frame arrival times, for the frame rate
  keys: new Set(), move: [0, 0, 0, 0, 0], action: false, lastSend: 0, lastTick: 0,
  drawing: false, newest: null,
  codec: 'jpeg',           // what this page asked for
  decoder: null, waitingForKey: true, // H.264
};
window.pathfarm = state;

function quantile(values, q) {
  if (values.length === 0) return NaN;
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))];
}

function keep(list, value) {
  list.push(value);
  if (list.length > KEEP_SAMPLES) list.shift();
}

function decodeFrame(buffer) {
  const v = new DataView(buffer);
  const magic = String.fromCharCode(v.getUint8(0), v.getUint8(1), v.getUint8(2), v.getUint8(3));
  if (buffer.byteLength < FRAME_HEADER_BYTES || magic !== 'PFWF' || v.getUint8(4) !== 1) {
    throw new Error('not a version-1 frame');
  }
  return {
    codec: v.getUint8(5), key: (v.getUint8(6) & 1) === 1,
    width: v.getUint16(8, true), height: v.getUint16(10, true),
    renderWidth: v.getUint16(12, true), renderHeight: v.getUint16(14, true),
    spp: v.getUint16(16, true), frame: Number(v.getBigUint64(24, true)),
    lastInput: Number(v.getBigUint64(32, true)),
    picture: new Uint8Array(buffer, FRAME_HEADER_BYTES),
  };
}

// Latency as the native client measures it (client/latency_stats.cpp): from sending an input
// to the arrival of the first frame whose echo covers it.
function frameArrived(header, now) {
  keep(state.arrivalsMs, now);
  for (const [sequence, sentAt] of state.sentAt) {
    if (sequence > header.lastInput) break;
    keep(state.latenciesMs, now - sentAt);
    state.latencyCount += 1;
    state.sentAt.delete(sequence);
  }
  state.frames += 1;
  state.lastHeader = header;
}

function show(image) {
  if (canvas.width !== image.displayWidth || canvas.height !== image.displayHeight) {
    canvas.width = image.displayWidth;
    canvas.height = image.displayHeight;
  }
  context.drawImage(image, 0, 0);
  image.close();
}

// H.264 pictures go to the decoder in order (each depends on the one before); after an error,
// or before the first picture, it waits for an IDR frame. A decoder error drops the socket:
// the coordinator sends a joining browser an IDR frame.
function decodeVideo(header) {
  if (!state.decoder || state.decoder.state === 'closed') {
    state.decoder = new VideoDecoder({
      output: show,
      error: (error) => {
        console.error('H.264', error);
        state.decoder = null;
        state.waitingForKey = true;
        if (state.socket) state.socket.close();
      },
    });
    state.decoder.configure({ codec: H264_CODEC, optimizeForLatency: true });
    state.waitingForKey = true;
  }
  if (state.waitingForKey && !header.key) return;
  state.waitingForKey = false;
  state.decoder.decode(new EncodedVideoChunk({
    type: header.key ? 'key' : 'delta', timestamp: header.frame * 100000, data: header.picture,
  }));
}

// Draws the newest JPEG; pictures that arrive while one is decoded replace each other.
async function draw() {
  if (state.drawing) return;
  state.drawing = true;
  while (state.newest) {
    const header = state.newest;
    state.newest = null;
    try {
      const image = await createImageBitmap(new Blob([header.picture], { type: 'image/jpeg' }));
      if (canvas.width !== image.width || canvas.height !== image.height) {
        canvas.width = image.width;
        canvas.height = image.height;
      }
      context.drawImage(image, 0, 0);
      image.close();
    } catch (error) {
      console.error('frame', header.frame, error);
    }
  }
  state.drawing = false;
}

function encodeInput(sequence, move, action) {
  const v = new DataView(new ArrayBuffer(36));
  'PFWI'.split('').forEach((c, k) => v.setUint8(k, c.charCodeAt(0)));
  v.setUint8(4, 1);
  v.setUint8(5, action ? 1 : 0);
  v.setBigUint64(8, BigInt(sequence), true);
  move.forEach((m, k) => v.setFloat32(16 + 4 * k, m, true));
  return v.buffer;
}

// H.264 where this browser can decode it (WebCodecs needs a secure context: https, or
// localhost), unless the URL says ?codec=jpeg.
async function chooseCodec() {
  if (new URLSearchParams(location.search).get('codec') === 'jpeg') return 'jpeg';
  if (!('VideoDecoder' in window)) return 'jpeg';
  try {
    const support = await VideoDecoder.isConfigSupported({ codec: H264_CODEC, optimizeForLatency: true });
    return support.supported ? 'h264' : 'jpeg';
  } catch (error) {
    return 'jpeg';
  }
}

function connect() {
  const query = new URLSearchParams({ codec: state.codec });
  const token = new URLSearchParams(location.search).get('token');
  if (token) query.set('token', token);
  const scheme = location.protocol === 'https:' ? 'wss://' : 'ws://';
  const socket = new WebSocket(scheme + location.host + '/ws?' + query.toString());
  socket.binaryType = 'arraybuffer';
  socket.onopen = () => { state.connected = true; };
  socket.onmessage = (event) => {
    const header = decodeFrame(event.data);
    frameArrived(header, performance.now());
    if (header.codec === CODEC_H264) {
      decodeVideo(header);
    } else {
      state.newest = header;
      draw();
    }
  };
  socket.onclose = () => {
    state.connected = false;
    state.socket = null;
    setTimeout(connect, 1000);
  };
  state.socket = socket;
}

// Gathers held keys into the pending move every tick; sends at most every 16 ms, and at once
// with the action key.
function tick(now) {
  const dt = state.lastTick ? (now - state.lastTick) / 1000 : 0;
  state.lastTick = now;
  const held = (code) => (state.keys.has(code) ? 1 : 0);
  const step = WALK_M_PER_S * dt, turn = TURN_RAD_PER_S * dt;
  state.move[0] += step * (held('KeyD') - held('KeyA'));
  state.move[1] += step * (held('Space') - held('ControlLeft'));
  state.move[2] += step * (held('KeyW') - held('KeyS'));
  state.move[3] += turn * (held('ArrowLeft') - held('ArrowRight'));
  state.move[4] += turn * (held('ArrowUp') - held('ArrowDown'));
  const any = state.action || state.move.some((m) => m !== 0);
  const socket = state.socket;
  if (any && socket && socket.readyState === WebSocket.OPEN &&
      (state.action || now - state.lastSend >= INPUT_PERIOD_MS)) {
    state.sequence += 1;
    socket.send(encodeInput(state.sequence, state.move, state.action));
    state.sentAt.set(state.sequence, now);
    state.move = [0, 0, 0, 0, 0];
    state.action = false;
    state.lastSend = now;
  }
  requestAnimationFrame(tick);
}

function showOverlay() {
  const a = state.arrivalsMs;
  const fps = a.length > 1 ? (1000 * (a.length - 1)) / (a[a.length - 1] - a[0]) : 0;
  const h = state.lastHeader;
  const ms = (q) => (state.latenciesMs.length ? quantile(state.latenciesMs, q).toFixed(0) : '-');
  overlay.textContent = !state.connected ? 'connecting…' :
    `${fps.toFixed(1)} frames/s   latency p50 ${ms(0.5)} ms  p99 ${ms(0.99)} ms\n` +
    (h ? `render ${h.renderWidth}x${h.renderHeight}  ${h.spp} spp   frame ${h.frame}  ` +
         (h.codec === CODEC_H264 ? 'H.264' : 'JPEG') : '');
}

document.addEventListener('keydown', (e) => {
  if (e.code === 'KeyE' && !e.repeat) state.action = true;
  state.keys.add(e.code);
  if (e.code.startsWith('Arrow') || e.code === 'Space') e.preventDefault();
});
document.addEventListener('keyup', (e) => state.keys.delete(e.code));
window.addEventListener('blur', () => state.keys.clear());
canvas.addEventListener('click', () => canvas.requestPointerLock());
document.addEventListener('mousemove', (e) => {
  if (document.pointerLockElement !== canvas) return;
  state.move[3] -= e.movementX * MOUSE_RAD_PER_PX;
  state.move[4] -= e.movementY * MOUSE_RAD_PER_PX;
});

chooseCodec().then((codec) => {
  state.codec = codec;
  connect();
});
requestAnimationFrame(tick);
setInterval(showOverlay, 250);
