// How the page writes numbers, and which of a result's numbers a view lists.
import { describe, expect, it } from 'vitest';
import { fmt, namedNumbers } from '../../src/format';
import { typeOf } from '../../src/downloads';

describe('numbers', () => {
  it('writes five significant digits, exponents below 1e-3 and from 1e6', () => {
    expect(fmt(0)).toBe('0');
    expect(fmt(1.234567)).toBe('1.2346');
    expect(fmt(-0.0001234567)).toBe('-1.2346e-4');
    expect(fmt(2_500_000)).toBe('2.5000e+6');
    expect(fmt(Number.NaN)).toBe('NaN');
  });
  it('lists the numbers at the keys asked for, in that order, skipping what is not a number', () => {
    const x = { b: 2, a: 1, s: 'bearings', n: null, list: [1] };
    expect(namedNumbers(x, ['a', 'b', 's', 'n', 'list'])).toEqual([['a', 1], ['b', 2]]);
  });
  it('saves JSON files as JSON, the others as text', () => {
    expect(typeOf('summary.json')).toBe('application/json');
    expect(typeOf('profiles/worn_7500h.dxf')).toBe('text/plain');
  });
});
