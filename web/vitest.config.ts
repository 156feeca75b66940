import { defineConfig } from 'vitest/config';

// The unit tests: pure functions of the page, run in Node (no browser, no worker). After the
// usual report, one line of counts for scripts/test's tally.
export default defineConfig({
  test: {
    include: ['tests/unit/**/*.test.ts'],
    reporters: ['default', './tests/unit/count-reporter.ts'],
  },
});
