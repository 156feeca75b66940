// A line for scripts/test's tally after the unit tests' usual report: `N passed, M failed (web
// unit tests)`, starting with the count as that tally reads it. A test file that cannot be
// loaded, or an error outside the tests, counts as a failure.
import type { Reporter, SerializedError, TestModule } from 'vitest/node';

export default class CountReporter implements Reporter {
  onTestRunEnd(modules: ReadonlyArray<TestModule>, unhandledErrors: ReadonlyArray<SerializedError>): void {
    let passed = 0;
    let failed = unhandledErrors.length;
    for (const m of modules) {
      for (const t of m.children.allTests()) {
        const state = t.result().state;
        if (state === 'passed') passed++;
        else if (state === 'failed') failed++;
      }
      if (m.errors().length > 0) failed++;
    }
    console.log(`${passed} passed, ${failed} failed (web unit tests)`);
  }
}
