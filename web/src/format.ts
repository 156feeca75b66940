// How the page writes the module's numbers: five significant digits, exponents for the very
// small and very large, and the named numbers of a result in the order a view lists them.

/** `v` to five significant digits, in exponent form below 1e-3 or from 1e6 on. */
export function fmt(v: number): string {
  if (!Number.isFinite(v)) return String(v);
  const a = Math.abs(v);
  return a !== 0 && (a < 1e-3 || a >= 1e6) ? v.toExponential(4) : Number(v.toPrecision(5)).toString();
}

/** The numbers of `obj` at `keys`, in that order; keys without a number (a loaded TE without a
 *  torque, a life beyond the horizon) are left out. */
export function namedNumbers<T extends object>(obj: T, keys: readonly (keyof T & string)[]): [string, number][] {
  const out: [string, number][] = [];
  for (const k of keys) {
    const v = obj[k];
    if (typeof v === 'number') out.push([k, v]);
  }
  return out;
}
