// The commands as the library declares them (generated/commands.ts, from
// `rvlife::api::commands`): the page's forms start from the declared defaults, so that the
// page, the command line and Python run the same command when nothing is changed.
import { COMMANDS } from './generated/commands';

/** The declared default of option `option` of the command line's command `command`, as a form
 *  shows it (`''`: none, the option absent unless given). Throws on a name the library does
 *  not declare: a form that names one is the page's error. */
export function declaredDefault(command: string, option: string): string {
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
