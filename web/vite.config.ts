import { defineConfig } from 'vite';

// A static site: relative asset paths, so the folder can be served from anywhere.
export default defineConfig({
  base: './',
  worker: { format: 'es' },
  build: { target: 'es2022', chunkSizeWarningLimit: 1500 },
});
