// The config in the page's address: the TOML text, deflated (the browser's CompressionStream)
// and base64url-encoded, so a design is shared as a link and nothing leaves the page.

async function pipe(bytes: Uint8Array, stream: CompressionStream | DecompressionStream): Promise<Uint8Array> {
  const out = new Blob([bytes as BlobPart]).stream().pipeThrough(stream);
  return new Uint8Array(await new Response(out).arrayBuffer());
}

export async function encodeConfig(text: string): Promise<string> {
  const z = await pipe(new TextEncoder().encode(text), new CompressionStream('deflate-raw'));
  let s = '';
  for (const b of z) s += String.fromCharCode(b);
  return btoa(s).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
}

export async function decodeConfig(code: string): Promise<string> {
  const b = atob(code.replace(/-/g, '+').replace(/_/g, '/'));
  const bytes = Uint8Array.from(b, (c) => c.charCodeAt(0));
  return new TextDecoder().decode(await pipe(bytes, new DecompressionStream('deflate-raw')));
}
