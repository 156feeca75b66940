import { describe, expect, it } from 'vitest';
import { partsFor, workerCount } from '../../src/parallel';

describe('the analysis workers', () => {
  it('are one per core up to four', () => {
    expect(workerCount('', 1)).toBe(1);
    expect(workerCount('', 2)).toBe(2);
    expect(workerCount('?c=abc', 12)).toBe(4);
  });
  it('follow workers=N in the address within 1 to 16, else the cores', () => {
    expect(workerCount('?workers=1', 8)).toBe(1);
    expect(workerCount('?c=x&workers=6', 2)).toBe(6);
    for (const bad of ['0', '17', '2.5', 'two', '']) expect(workerCount(`?workers=${bad}`, 2)).toBe(2);
  });
});

describe('a Monte Carlo run in parts', () => {
  it('has one sample a part up to eight parts a worker, never none', () => {
    expect(partsFor(16, 2)).toBe(16);
    expect(partsFor(100, 2)).toBe(16);
    expect(partsFor(3, 4)).toBe(3);
    expect(partsFor(1, 0)).toBe(1);
  });
  it('covers every sample once: the library cuts part i of n at floor(i S / n)', () => {
    for (const [s, w] of [[16, 2], [100, 3], [7, 4], [1, 1]]) {
      const n = partsFor(s, w);
      const sizes = Array.from({ length: n }, (_, k) => Math.floor(((k + 1) * s) / n) - Math.floor((k * s) / n));
      expect(sizes.reduce((a, b) => a + b, 0)).toBe(s);
      expect(Math.min(...sizes)).toBeGreaterThan(0);
    }
  });
});
