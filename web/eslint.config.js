// The linter's rules for the page's TypeScript and its tests: the recommended sets for
// JavaScript and TypeScript, and no `any` (what the module answers is typed in src/types.ts
// and src/protocol.ts). The module's binding (src/pkg) is generated and not linted.
import js from '@eslint/js';
import { defineConfig } from 'eslint/config';
import tseslint from 'typescript-eslint';

// What the end-to-end test uses of Node and, in the functions it runs in the page, of the
// browser.
const e2eGlobals = Object.fromEntries([
  'console', 'process', 'performance', 'fetch', 'setTimeout', 'clearTimeout', 'URL',
  'document', 'location', 'PerformanceObserver',
].map((name) => [name, 'readonly']));

export default defineConfig(
  { ignores: ['dist/', 'src/pkg/'] },
  js.configs.recommended,
  tseslint.configs.recommended,
  { rules: { '@typescript-eslint/no-explicit-any': 'error' } },
  { files: ['tests/**/*.mjs'], languageOptions: { globals: e2eGlobals } },
);
