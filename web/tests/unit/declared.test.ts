// The page's forms start from the library's declared defaults (generated/commands.ts).
import { describe, expect, it } from 'vitest';
import { declaredDefault, declaredField } from '../../src/declared';
import { COMMANDS } from '../../src/generated/commands';

describe('the declared defaults', () => {
  it('are the command line\'s defaults, as a form shows them', () => {
    expect(declaredDefault('montecarlo', 'samples')).toBe('100');
    expect(declaredDefault('montecarlo', 'seed')).toBe('1');
    expect(declaredDefault('hysteresis', 'levels')).toBe('10');
    expect(declaredDefault('hysteresis', 'crank_deg')).toBe('0');
    expect(declaredDefault('optimize', 'objective')).toBe('life');
  });
  it('leave blank an option that is absent unless given', () => {
    expect(declaredDefault('te', 'torque_nm')).toBe('');
  });
  it('refuse an option the library does not declare', () => {
    // @ts-expect-error: the type check refuses it first.
    expect(() => declaredDefault('hysteresis', 'level')).toThrow(/no option level/);
  });
  it('name a page command for every command the page runs', () => {
    expect(COMMANDS.filter((c) => c.page !== null).map((c) => c.name)).toContain('montecarlo');
  });
});

describe('the declared fields', () => {
  it('take their unit and help from the declaration, the value from the page or the default', () => {
    const torque = declaredField('contact', 'torque_nm', { id: 'torque', label: 'output torque', value: '412' });
    const decl = COMMANDS.find((c) => c.name === 'contact')!.options.find((o) => o.name === 'torque_nm')!;
    expect(torque).toEqual({ id: 'torque', label: 'output torque', value: '412', unit: 'N m', help: decl.help });
    expect(torque.help).toMatch(/N m/);
    expect(declaredField('hysteresis', 'levels', { id: 'levels', label: 'torque levels' }).value).toBe('10');
    expect(declaredField('te', 'hours', { id: 'hours', label: 'worn at' }).unit).toBe('h');
  });
  it('refuse an option the page does not take', () => {
    expect(() => declaredField('te', 'json', { id: 'json', label: 'json' })).toThrow(/not the page's/);
  });
});
