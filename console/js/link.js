// The console's connection to omniviewd (subprotocol omniview.console.v1, docs/API.md "Web
// endpoint"): authentication, the API's calls as promises, and subscribed views' frames.

export class ApiError extends Error {
  constructor(code, message) {
    super(message);
    this.code = code;
  }
}

export class Link extends EventTarget {
  constructor(url) {
    super();
    this.url = url;
    this.nextId = 1;
    this.pending = new Map();   // call id -> {resolve, reject}
    this.channels = new Map();  // channel -> handler(header, bytes)
    this.role = null;
  }

  // Resolves with the hello message once open; `token` (may be null) is sent first when the
  // daemon asks for one.
  open(token) {
    return new Promise((resolve, reject) => {
      const ws = new WebSocket(this.url, ['omniview.console.v1']);
      ws.binaryType = 'arraybuffer';
      this.ws = ws;
      let hello = null;
      ws.onmessage = (event) => {
        if (typeof event.data !== 'string') return this.onFrame(event.data);
        const msg = JSON.parse(event.data);
        if (msg.op === 'hello') {
          hello = msg;
          if (msg.auth === 'required') {
            if (!token) return reject(new ApiError('UNAUTHENTICATED', 'this daemon needs a token'));
            this.call(null, null, { op: 'auth', token }).then((r) => {
              this.role = r.role;
              resolve(hello);
            }, reject);
          } else {
            this.role = msg.role || 'operator';
            resolve(hello);
          }
          return;
        }
        this.onText(msg);
      };
      ws.onclose = (event) => {
        const error = new ApiError('UNAVAILABLE', event.reason || 'connection closed (' + event.code + ')');
        for (const p of this.pending.values()) p.reject(error);
        this.pending.clear();
        if (!hello) reject(error);
        this.dispatchEvent(new CustomEvent('close', { detail: { code: event.code, reason: event.reason } }));
      };
    });
  }

  close() { if (this.ws) this.ws.close(1000, 'console closed'); }

  onText(msg) {
    if (msg.op === 'reply') {
      const p = this.pending.get(msg.id);
      if (!p) return;
      this.pending.delete(msg.id);
      if (msg.error) p.reject(new ApiError(msg.error.code, msg.error.message));
      else p.resolve(msg.response);
    } else if (msg.op === 'ended') {
      const handler = this.channels.get(msg.channel);
      this.channels.delete(msg.channel);
      if (handler) handler(null, null, msg.error);
    } else if (msg.op === 'error') {
      this.dispatchEvent(new CustomEvent('error', { detail: msg.error }));
    }
  }

  onFrame(buffer) {
    const view = new DataView(buffer);
    const channel = view.getUint32(0, true);
    const headerLength = view.getUint32(4, true);
    const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 8, headerLength)));
    const handler = this.channels.get(channel);
    if (handler) handler(header, new Uint8Array(buffer, 8 + headerLength));
  }

  // The API's unary call `method` with `request` (its proto3 JSON); resolves with the response.
  call(method, request, raw) {
    const id = this.nextId++;
    const msg = raw ? { ...raw, id } : { op: 'call', id, method, request: request || {} };
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject });
      this.ws.send(JSON.stringify(msg));
    });
  }

  // Frames of `view`: onFrame(header, jpegBytes) for each, onFrame(null, null, error) at the end.
  async subscribe(view, options, onFrame) {
    const r = await this.call(null, null, { op: 'subscribe', view, ...options });
    this.channels.set(r.channel, onFrame);
    return r.channel;
  }

  async unsubscribe(channel) {
    this.channels.delete(channel);
    if (this.ws.readyState === WebSocket.OPEN) await this.call(null, null, { op: 'unsubscribe', channel });
  }
}
