// The commands as the library declares them (generated/commands.ts, from
// `rvlife::api::commands`): the page's forms start from the declared defaults, so that the
// page, the command line and Python run the same command when nothing is changed.
import { COMMANDS } from './generated/commands';

type Declared = (typeof COMMANDS)[number];
/** A command's name on the command line. */
export type CommandName = Declared['name'];
/** The options command `C` declares. */
export type OptionOf<C extends CommandName> = Extract<Declared, { name: C }>['options'][number]['name'];

/** The declared default of option `option` of the command line's command `command`, as a form
 *  shows it (`''`: none, the option absent unless given). Both names are typed from the
 *  declaration: a form that names what the library does not declare fails the type check. */
export function declaredDefault<C extends CommandName>(command: C, option: OptionOf<C>): string {
  const c = COMMANDS.find((x) => x.name === command);
  const o = c?.options.find((x) => x.name === option);
  if (!o) throw new Error(`rvlife ${command} has no option ${option}`);
  const d: unknown = o.default;
  if (typeof d === 'object' && d !== null) {
    const v = Object.values(d)[0];
    return typeof v === 'number' || typeof v === 'string' ? String(v) : '';
  }
  return '';
}
