// The editor's logic without the page: what a box shows, what a typed value becomes, the key
// a message names, the sections, and the values the config refused.
import { describe, expect, it } from 'vitest';
import {
  Refusals, keyNote, keyOf, lastStageHours, placeholder, ratedTorque, sections, shortKey, toleranceMeaning, toleranceOf, typed, valueText,
} from '../../src/keys';
import type { KeyDoc } from '../../src/types';

const key = (k: Partial<KeyDoc> & { key: string }): KeyDoc => ({
  section: k.key.includes('.') ? k.key.slice(0, k.key.lastIndexOf('.')) : '',
  value: null, commented: null, comment: '', unit: '', allowed: null, ...k,
});

describe('typed: what the user wrote as the JSON value of a key', () => {
  it('reads numbers, booleans and lists as JSON', () => {
    expect(typed(' 2.5 ', 40)).toBe('2.5');
    expect(typed('true', false)).toBe('true');
    expect(typed('[0, 3750,7500]', [0])).toBe('[0,3750,7500]');
  });
  it('keeps a string key\'s text as it is, spaces and digits included', () => {
    expect(typed(' 42 ', 'rigid')).toBe('" 42 "');
  });
  it('turns what is not JSON into a string, which a number key then refuses', () => {
    expect(typed('abc', 40)).toBe('"abc"');
    expect(typed('2,5', 40)).toBe('"2,5"');
  });
  it('removes the key when the box is blank', () => {
    expect(typed('   ', 40)).toBe('null');
  });
  it('round-trips what a box shows', () => {
    for (const v of [40, 0.025, true, [0, 3750, 7500], 'flexible']) {
      expect(JSON.parse(typed(valueText(v), v))).toEqual(v);
    }
    expect(valueText(null)).toBe('');
  });
});

describe('tolerances: shown as their TOML with their meaning, and typed back', () => {
  it('shows a tolerance as its TOML, not as JSON', () => {
    expect(valueText({ normal: 1 })).toBe('normal = 1');
    expect(valueText({ uniform: 4 })).toBe('uniform = 4');
    expect(valueText({ iso_grade: 5 })).toBe('iso_grade = 5');
    // Not one distribution: as JSON still.
    expect(valueText({ normal: 1, uniform: 2 })).toBe('{"normal":1,"uniform":2}');
    expect(toleranceOf({ sigma: 1 })).toBeNull();
  });
  it('says what each distribution means, in the key\'s unit', () => {
    expect(toleranceMeaning({ normal: 1 }, 'um')).toBe('normal, 1 sigma = 1 um: each part\'s error drawn about zero with standard deviation 1 um (99.7 % within +-3 um)');
    expect(toleranceMeaning({ uniform: 4 }, 'um')).toBe('uniform within +-4 um: each part\'s error drawn evenly between -4 and +4 um (1 sigma = 2.3094 um)');
    expect(toleranceMeaning({ iso_grade: 5 }, 'um')).toMatch(/^normal, 1 sigma = IT5\/12 of the feature's size \(ISO 286-1 grade 5\)/);
    expect(toleranceMeaning(40, '')).toBeNull();
  });
  it('round-trips what the box shows to the same value, and reads the TOML typed', () => {
    for (const v of [{ normal: 1 }, { normal: 0.5 }, { uniform: 4 }, { iso_grade: 5 }]) {
      expect(JSON.parse(typed(valueText(v), v))).toEqual(v);
    }
    expect(typed('{ normal = 1.5 }', null)).toBe('{"normal":1.5}');
    // A deviation or a limit written as a float (the file's `2.0`), a grade as a whole number.
    expect(typed('uniform: 2', { normal: 1 })).toBe('{"uniform":2.0}');
    expect(typed('normal = 1', { normal: 1 })).toBe('{"normal":1.0}');
    expect(typed('iso_grade = 6', { normal: 1 })).toBe('{"iso_grade":6}');
    expect(typed('{"iso_grade":6}', { normal: 1 })).toBe('{"iso_grade":6}');
    // Not a number: a string, which the config then refuses.
    expect(typed('normal = x', { normal: 1 })).toBe('"normal = x"');
  });
});

describe('keyOf: the key an error message names', () => {
  it('finds the key of an invalid value', () => {
    expect(keyOf('invalid cycloid.eccentricity_mm = -1: allowed 0 < value <= 20')).toBe('cycloid.eccentricity_mm');
  });
  it('finds a key quoted after "at", without its list index', () => {
    expect(keyOf('config.toml: expected a number at `wear.stage_hours[2]`')).toBe('wear.stage_hours');
  });
  it('finds none in a message that names no key', () => {
    expect(keyOf('the config could not be read')).toBeNull();
  });
});

describe('the editor\'s rows', () => {
  const keys = [
    key({ key: 'name', value: 'example' }),
    key({ key: 'cycloid.pins', value: 40, unit: '' }),
    key({ key: 'reducer.rated_torque_nm', value: 412, unit: 'N m' }),
    key({ key: 'cycloid.eccentricity_mm', value: 1.3, unit: 'mm', commented: '1.3', comment: 'crank throw' }),
    key({ key: 'wear.stage_hours', value: [0, 3750, 7500] }),
  ];
  it('groups the keys by section in the order they come, top-level keys first under (top)', () => {
    const s = sections(keys);
    expect([...s.keys()]).toEqual(['(top)', 'cycloid', 'reducer', 'wear']);
    expect(s.get('cycloid')!.map(shortKey)).toEqual(['pins', 'eccentricity_mm']);
    expect(shortKey(keys[0])).toBe('name');
  });
  it('notes the example value and the comment', () => {
    expect(keyNote(keys[3])).toBe('default / example: 1.3. crank throw');
    expect(placeholder(keys[3])).toBe('default 1.3');
    expect(keyNote(key({ key: 'a.b', comment: 'why' }))).toBe('why');
  });
  it('reads the last stage\'s hours and the rated torque', () => {
    expect(lastStageHours(keys)).toBe(7500);
    expect(ratedTorque(keys)).toBe(412);
    expect(lastStageHours([])).toBe(0);
    expect(ratedTorque([])).toBe(0);
  });
});

describe('Refusals: the values the config refused', () => {
  it('keeps a refused value refused through later validations of the text', () => {
    const r = new Refusals();
    r.refuse('cycloid.pins', 'invalid cycloid.pins = 2.5: an integer');
    // Another key edited: the text validates, the refused box still holds the config.
    expect(r.valid(null)).toBe(false);
    expect(r.first()).toBe('cycloid.pins');
    expect([...r.entries()]).toEqual([['cycloid.pins', 'invalid cycloid.pins = 2.5: an integer']]);
  });
  it('lifts a key\'s refusal when the config takes a value of it, and only that key\'s', () => {
    const r = new Refusals();
    r.refuse('cycloid.pins', 'a');
    r.refuse('reducer.rated_torque_nm', 'b');
    r.accept('cycloid.pins');
    expect(r.size).toBe(1);
    expect(r.first()).toBe('reducer.rated_torque_nm');
    r.accept('reducer.rated_torque_nm');
    expect(r.valid(null)).toBe(true);
  });
  it('forgets every refusal with a new text, but not the new text\'s own message', () => {
    const r = new Refusals();
    r.refuse('cycloid.pins', 'a');
    r.clear();
    expect(r.first()).toBeUndefined();
    expect(r.valid(null)).toBe(true);
    expect(r.valid('invalid cycloid.pins = 0')).toBe(false);
  });
});
