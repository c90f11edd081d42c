// Reads the job's image.exr in the browser, so that the final-image viewer can show each
// layer (AOV) with any exposure from the linear values, not from the tone-mapped preview.
//
// Only what the farm writes is read: FLOAT or HALF channels, scanline or one-level tiled
// files, without compression or with ZIP/ZIPS (zlib, inflated by the browser's
// DecompressionStream). Anything else is refused with an ExrError naming it.
export class ExrError extends Error {
    constructor(message) {
        super(`image.exr: ${message}`);
        this.name = "ExrError";
    }
}
const MAGIC = 20000630;
const TILED_FLAG = 0x200;
const HALF = 1;
const FLOAT = 2;
const NO_COMPRESSION = 0;
const ZIPS_COMPRESSION = 2;
const ZIP_COMPRESSION = 3;
/** A little-endian cursor over the file. */
class Reader {
    constructor(view) {
        this.view = view;
        this.pos = 0;
    }
    u8() {
        return this.view.getUint8(this.pos++);
    }
    i32() {
        const v = this.view.getInt32(this.pos, true);
        this.pos += 4;
        return v;
    }
    u32() {
        const v = this.view.getUint32(this.pos, true);
        this.pos += 4;
        return v;
    }
    u64() {
        const lo = this.view.getUint32(this.pos, true);
        const hi = this.view.getUint32(this.pos + 4, true);
        this.pos += 8;
        return hi * 2 ** 32 + lo;
    }
    string() {
        let s = "";
        for (let c = this.u8(); c !== 0; c = this.u8())
            s += String.fromCharCode(c);
        return s;
    }
}
function readHeader(r) {
    if (r.i32() !== MAGIC)
        throw new ExrError("not an OpenEXR file");
    const version = r.i32();
    if ((version & ~(0xff | TILED_FLAG)) !== 0)
        throw new ExrError("multi-part and deep files are not shown");
    const header = {};
    for (let name = r.string(); name !== ""; name = r.string()) {
        r.string(); // the attribute's type name: the attribute's name says what it is
        const size = r.i32();
        const end = r.pos + size;
        if (name === "channels") {
            header.channels = [];
            for (let ch = r.string(); ch !== ""; ch = r.string()) {
                const type = r.i32();
                r.pos += 4; // pLinear and reserved
                if (r.i32() !== 1 || r.i32() !== 1)
                    throw new ExrError(`channel ${ch} is subsampled`);
                if (type !== HALF && type !== FLOAT)
                    throw new ExrError(`channel ${ch} is not HALF or FLOAT`);
                header.channels.push({ name: ch, type });
            }
        }
        else if (name === "compression") {
            header.compression = r.u8();
        }
        else if (name === "dataWindow") {
            const [x0, y0, x1, y1] = [r.i32(), r.i32(), r.i32(), r.i32()];
            Object.assign(header, { xMin: x0, yMin: y0, width: x1 - x0 + 1, height: y1 - y0 + 1 });
        }
        else if (name === "tiles") {
            header.tile = { x: r.u32(), y: r.u32(), mode: r.u8() & 0x0f };
        }
        r.pos = end;
    }
    if (!header.channels || header.compression === undefined || header.width === undefined) {
        throw new ExrError("the header lacks channels, compression or dataWindow");
    }
    if (![NO_COMPRESSION, ZIPS_COMPRESSION, ZIP_COMPRESSION].includes(header.compression)) {
        throw new ExrError(`compression ${header.compression} is not shown (only none, ZIPS and ZIP)`);
    }
    if (header.tile && header.tile.mode !== 0)
        throw new ExrError("mip-mapped tiles are not shown");
    return header;
}
async function inflate(bytes) {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
    return new Uint8Array(await new Response(stream).arrayBuffer());
}
/** Undoes ZIP's byte predictor and its split of even and odd bytes. */
function unpredict(t) {
    for (let i = 1; i < t.length; i++)
        t[i] = (t[i - 1] + t[i] - 128) & 0xff;
    const out = new Uint8Array(t.length);
    const half = (t.length + 1) >> 1;
    for (let i = 0; i < t.length; i++)
        out[i] = i % 2 === 0 ? t[i >> 1] : t[half + (i >> 1)];
    return out;
}
function halfToFloat(h) {
    const e = (h >> 10) & 0x1f;
    const m = h & 0x3ff;
    const sign = h & 0x8000 ? -1 : 1;
    if (e === 0)
        return sign * m * 2 ** -24;
    if (e === 31)
        return m ? NaN : sign * Infinity;
    return sign * (1 + m / 1024) * 2 ** (e - 15);
}
/**
 * Copies one block (a tile or a run of scanlines): for each of its rows, each channel's
 * values of the row, channels in the header's order.
 */
function placeBlock(h, img, data, x0, y0, w, rows) {
    const view = new DataView(data.buffer, data.byteOffset, data.byteLength);
    let p = 0;
    for (let y = y0; y < y0 + rows; y++) {
        for (const ch of h.channels) {
            const dst = img.channels.get(ch.name);
            const row = y * img.width;
            for (let x = x0; x < x0 + w; x++) {
                if (ch.type === FLOAT) {
                    dst[row + x] = view.getFloat32(p, true);
                    p += 4;
                }
                else {
                    dst[row + x] = halfToFloat(view.getUint16(p, true));
                    p += 2;
                }
            }
        }
    }
}
/** Decodes an image.exr's bytes. */
export async function decodeExr(buffer) {
    const r = new Reader(new DataView(buffer));
    const h = readHeader(r);
    const img = { width: h.width, height: h.height, channels: new Map() };
    for (const ch of h.channels)
        img.channels.set(ch.name, new Float32Array(h.width * h.height));
    const pixelBytes = h.channels.reduce((n, ch) => n + (ch.type === FLOAT ? 4 : 2), 0);
    const rowsPerChunk = h.compression === ZIP_COMPRESSION ? 16 : 1;
    const tile = h.tile;
    const chunks = tile
        ? Math.ceil(h.width / tile.x) * Math.ceil(h.height / tile.y)
        : Math.ceil(h.height / rowsPerChunk);
    const offsets = [];
    for (let i = 0; i < chunks; i++)
        offsets.push(r.u64());
    const bytes = new Uint8Array(buffer);
    for (const offset of offsets) {
        r.pos = offset;
        let x0 = 0;
        let y0;
        let w = h.width;
        let rows;
        if (tile) {
            const tx = r.i32();
            const ty = r.i32();
            r.pos += 8; // the level, always 0 for one-level files
            x0 = tx * tile.x;
            y0 = ty * tile.y;
            w = Math.min(tile.x, h.width - x0);
            rows = Math.min(tile.y, h.height - y0);
        }
        else {
            y0 = r.i32() - h.yMin;
            rows = Math.min(rowsPerChunk, h.height - y0);
        }
        const size = r.i32();
        if (size < 0 || r.pos + size > buffer.byteLength)
            throw new ExrError("a chunk runs past the end of the file");
        let data = bytes.subarray(r.pos, r.pos + size);
        // A block that did not shrink is stored as it is.
        if (h.compression !== NO_COMPRESSION && size < w * rows * pixelBytes)
            data = unpredict(await inflate(data));
        if (data.length !== w * rows * pixelBytes)
            throw new ExrError(`a chunk at row ${y0} holds ${data.length} bytes, want ${w * rows * pixelBytes}`);
        placeBlock(h, img, data, x0, y0, w, rows);
    }
    return img;
}
