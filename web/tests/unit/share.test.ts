// The config in the page's address: deflated, base64url, and back.
import { describe, expect, it } from 'vitest';
import { decodeConfig, encodeConfig } from '../../src/share';

const CONFIG = `# An RV reducer
[reducer]
rated_torque_nm = 412.0 # N m

[cycloid]
pins = 40
eccentricity_mm = 1.3

[wear]
stage_hours = [0.0, 3750.0, 7500.0]
`;

describe('the config in the URL', () => {
  it('round-trips the text byte for byte, comments and layout kept', async () => {
    expect(await decodeConfig(await encodeConfig(CONFIG))).toBe(CONFIG);
  });
  it('round-trips text beyond ASCII and the empty text', async () => {
    const text = 'comment = "± 3 % of the rated torque, 0.5′ lost motion"\n';
    expect(await decodeConfig(await encodeConfig(text))).toBe(text);
    expect(await decodeConfig(await encodeConfig(''))).toBe('');
  });
  it('is safe in an address: base64url without padding, and shorter than a long config', async () => {
    const long = CONFIG.repeat(50);
    const code = await encodeConfig(long);
    expect(code).toMatch(/^[A-Za-z0-9_-]+$/);
    expect(code.length).toBeLessThan(long.length / 4);
    expect(await decodeConfig(code)).toBe(long);
  });
  it('refuses what is not a config it encoded', async () => {
    await expect(decodeConfig('not-a-config')).rejects.toThrow();
  });
});
