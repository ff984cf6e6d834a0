// A view's H.264 stream decoded by the browser (WebCodecs), onto the pane's canvas.
//
// The daemon sends Annex-B access units, SPS/PPS with every key frame, and starts (and
// resumes after a drop) each client at a key frame. The decoder is configured from the
// first key frame's SPS, with no `description`: WebCodecs then reads Annex-B and takes the
// parameter sets in-band. Nothing is decoded before that key frame (a delta frame without
// its references is a broken picture, or a decoder error).

// Annex-B byte stream -> NAL units (Uint8Array views, start codes removed).
export function nalUnits(bytes) {
  const units = [];
  let start = -1;
  for (let i = 0; i + 2 < bytes.length; i++) {
    if (bytes[i] === 0 && bytes[i + 1] === 0 && bytes[i + 2] === 1) {
      if (start >= 0) units.push(bytes.subarray(start, bytes[i - 1] === 0 ? i - 1 : i));
      start = i + 3;
      i += 2;
    }
  }
  if (start >= 0 && start < bytes.length) units.push(bytes.subarray(start));
  return units;
}

export const nalType = (unit) => unit[0] & 0x1f;

// Whether an access unit holds an IDR slice (type 5): a picture decodable on its own.
export function isKeyFrame(bytes) {
  return nalUnits(bytes).some((u) => nalType(u) === 5);
}

// The codec string of a stream from its SPS (type 7): "avc1." + profile_idc,
// constraint flags and level_idc, each as two hex digits (RFC 6381), e.g. avc1.64001F.
export function codecFromAccessUnit(bytes) {
  const sps = nalUnits(bytes).find((u) => nalType(u) === 7);
  if (!sps || sps.length < 4) return null;
  const hex = (b) => b.toString(16).toUpperCase().padStart(2, '0');
  return 'avc1.' + hex(sps[1]) + hex(sps[2]) + hex(sps[3]);
}

// Whether this browser may decode the daemon's H.264 (High profile, level 4.0 covers the
// views' sizes): {ok, reason}. WebCodecs exists only in secure contexts (https, or http on
// localhost/127.0.0.1), so a console over plain http on the network gets JPEG.
export async function h264Support(codec = 'avc1.640028') {
  if (typeof VideoDecoder === 'undefined' || typeof EncodedVideoChunk === 'undefined') {
    return { ok: false, reason: window.isSecureContext ? 'no WebCodecs' : 'no WebCodecs (not https)' };
  }
  try {
    const r = await VideoDecoder.isConfigSupported({ codec, optimizeForLatency: true });
    return r.supported ? { ok: true } : { ok: false, reason: `${codec} not supported` };
  } catch (e) {
    return { ok: false, reason: `${codec}: ${e.message}` };
  }
}

// Decoded frames a slow browser may have queued before it skips ahead (latency over a
// smooth picture: the console is for steering).
const MAX_QUEUED = 4;
// Delta frames without a key frame before asking for one (a new subscription starts at one).
const MAX_WAITED = 30;

// Feeds one stream's access units to a VideoDecoder. onPicture(videoFrame) owns the frame
// (it must close it); onError(reason) once, after which the stream is given up;
// onResync() when it needs a key frame soon (it fell behind, or none came).
export class H264Stream {
  constructor(onPicture, onError, onResync = () => {}) {
    this.onPicture = onPicture;
    this.onError = onError;
    this.onResync = onResync;
    this.decoder = null;
    this.codec = null;
    this.keySeen = false;  // a key frame went in since (re)configuring
    this.waited = 0;       // delta frames skipped while waiting for one
    this.firstKey = null;  // whether the first access unit was a key frame (as the daemon promises)
    this.failed = false;
    this.timestamp = 0;
    this.queue = Promise.resolve();
  }

  // In arrival order, each after the one before (a key frame may wait for a config check).
  push(bytes) {
    // A throw (configure() refusing what isConfigSupported accepted) gives up the stream
    // rather than leaving the chain rejected, which would skip every later frame.
    this.queue = this.queue.then(() => this.pushNow(bytes)).catch((e) => this.fail(String(e && e.message || e)));
    return this.queue;
  }

  async pushNow(bytes) {
    if (this.failed) return;
    const key = isKeyFrame(bytes);
    if (this.firstKey === null) this.firstKey = key;
    if (key) {
      const codec = codecFromAccessUnit(bytes);
      if (!codec) return this.fail('key frame without an SPS');
      if (codec !== this.codec) {
        // First key frame, or a new SPS (the view's size or level changed): configure anew.
        const support = await h264Support(codec);
        if (this.failed) return;
        if (!support.ok) return this.fail(support.reason);
        this.configure(codec);
      }
      this.keySeen = true;
    } else if (!this.keySeen) {
      if (++this.waited % MAX_WAITED === 0) this.onResync();
      return;
    } else if (this.decoder.decodeQueueSize > MAX_QUEUED) {
      // Too far behind: what follows depends on frames not decoded yet, so skip to the next
      // key frame rather than queue more.
      this.keySeen = false;
      this.waited++;
      this.onResync();
      return;
    }
    try {
      this.decoder.decode(new EncodedVideoChunk({ type: key ? 'key' : 'delta', timestamp: this.timestamp, data: bytes }));
      this.timestamp += 1;
    } catch (e) {
      this.fail('decode: ' + e.message);
    }
  }

  configure(codec) {
    if (this.decoder && this.decoder.state !== 'closed') this.decoder.close();
    this.decoder = new VideoDecoder({
      output: (frame) => (this.failed ? frame.close() : this.onPicture(frame)),
      error: (e) => this.fail('decoder: ' + e.message),
    });
    this.decoder.configure({ codec, optimizeForLatency: true });
    this.codec = codec;
    this.keySeen = false;
  }

  fail(reason) {
    if (this.failed) return;
    this.failed = true;
    this.close();
    this.onError(reason);
  }

  close() {
    if (this.decoder && this.decoder.state !== 'closed') this.decoder.close();
    this.decoder = null;
  }
}
