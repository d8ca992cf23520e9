// The HTTP API of orcs-view (docs/viewer-api.md): JSON descriptions, raw little-endian arrays for channels.

export class ApiError extends Error {}

let token = null;
/** The live control token, sent as X-Orcs-Token on every POST once claimed. */
export function setToken(value) { token = value; }
export function getToken() { return token; }

async function request(url, options = {}) {
  let response;
  try {
    response = await fetch(url, options);
  } catch (err) {
    throw new ApiError(`${options.method || 'GET'} ${url}: the server does not answer (${err.message})`);
  }
  if (!response.ok) {
    let text = '';
    try { text = (await response.text()).trim(); } catch { /* no body */ }
    try {
      const parsed = JSON.parse(text);
      if (parsed && typeof parsed === 'object' && (parsed.error || parsed.message)) text = parsed.error || parsed.message;
    } catch { /* plain text */ }
    const err = new ApiError(`${options.method || 'GET'} ${url}: ${response.status}${text ? ' — ' + text : ''}`);
    err.status = response.status;
    err.reason = text;
    throw err;
  }
  return response;
}

export async function getJson(url, options) {
  const response = await request(url, options);
  return response.json();
}

export async function getFloat64(url) {
  const buffer = await (await request(url)).arrayBuffer();
  return new Float64Array(buffer);
}

export async function getFloat32(url) {
  const buffer = await (await request(url)).arrayBuffer();
  return new Float32Array(buffer);
}

export async function post(url, body, { raw = false } = {}) {
  const headers = {};
  if (token) headers['X-Orcs-Token'] = token;
  let payload = body;
  if (!raw && body !== undefined) {
    headers['Content-Type'] = 'application/json';
    payload = JSON.stringify(body);
  }
  const response = await request(url, { method: 'POST', headers, body: payload });
  const text = await response.text();
  if (!text) return null;
  try { return JSON.parse(text); } catch { return text; }
}

/** The server answers at most this many values (channels × frames) per request (docs/viewer-api.md). */
const MAX_CHANNEL_VALUES = 1 << 22;

/**
 * Fetches the values of many channels of a recording, in requests of at most 1000 channels (the URL stays short)
 * and MAX_CHANNEL_VALUES values. Returns id -> Float32Array.
 */
export async function getChannels(rid, ids, frames) {
  const out = new Map();
  const unique = [...new Set(ids)].filter((id) => Number.isInteger(id) && id >= 0);
  const perRequest = Math.max(1, Math.min(1000, Math.floor(MAX_CHANNEL_VALUES / Math.max(frames, 1))));
  for (let start = 0; start < unique.length; start += perRequest) {
    const chunk = unique.slice(start, start + perRequest);
    const data = await getFloat32(`/api/recording/${encodeURIComponent(rid)}/channels?ids=${chunk.join(',')}&frames=${frames}`);
    const n = chunk.length ? Math.floor(data.length / chunk.length) : 0;
    if (n !== frames) throw new ApiError(`recording ${rid}: ${data.length} channel values for ${chunk.length} channels of ${frames} frames`);
    chunk.forEach((id, i) => out.set(id, data.subarray(i * n, (i + 1) * n)));
  }
  return out;
}
