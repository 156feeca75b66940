// The commands as the library declares them (generated/commands.ts, from
// `rvlife::api::commands`): the page's forms start from the declared defaults, so that the
// page, the command line and Python run the same command when nothing is changed.
import { COMMANDS } from './generated/commands';
import type { Field } from './ui';

type Declared = (typeof COMMANDS)[number];
/** A command's name on the command line. */
export type CommandName = Declared['name'];
/** The options command `C` declares. */
export type OptionOf<C extends CommandName> = Extract<Declared, { name: C }>['options'][number]['name'];

/** The declaration of option `option` of command `command`.
 *  @throws when the command does not declare it (the types refuse it first). */
function declaredOption<C extends CommandName>(command: C, option: OptionOf<C>) {
  const o = COMMANDS.find((x) => x.name === command)?.options.find((x) => x.name === option);
  if (!o) throw new Error(`rvlife ${command} has no option ${option}`);
  return o;
}

/** The declared default of option `option` of the command line's command `command`, as a form
 *  shows it (`''`: none, the option absent unless given). Both names are typed from the
 *  declaration: a form that names what the library does not declare fails the type check. */
export function declaredDefault<C extends CommandName>(command: C, option: OptionOf<C>): string {
  const d: unknown = declaredOption(command, option).default;
  if (typeof d === 'object' && d !== null) {
    const v = Object.values(d)[0];
    return typeof v === 'number' || typeof v === 'string' ? String(v) : '';
  }
  return '';
}

/** A form's field for option `option` of command `command`: its unit and its help (the
 *  command line's `--help` text, shown as the field's tooltip) from the declaration, its
 *  value the declared default unless the page gives one (`value`: the page's own start, such
 *  as the config's rated torque). */
export function declaredField<C extends CommandName>(
  command: C,
  option: OptionOf<C>,
  field: { id: string; label: string; value?: string; choices?: string[] },
): Field {
  const o = declaredOption(command, option);
  if (!(o.fronts as readonly string[]).includes('page')) throw new Error(`rvlife ${command} --${option} is not the page's`);
  return {
    ...field,
    value: field.value ?? declaredDefault(command, option),
    unit: o.unit,
    help: o.help,
  };
}
