// The page's handle on rvlife: each call runs in a Web Worker and returns a promise; a long
// command can be cancelled (its worker is terminated and a fresh one started).

export type Progress = (done: number, total: number) => void;

type Pending = { resolve: (v: any) => void; reject: (e: Error) => void; progress?: Progress };

export class Cancelled extends Error {
  constructor() { super('cancelled'); }
}

export class Engine {
  private worker!: Worker;
  private next = 1;
  private pending = new Map<number, Pending>();

  constructor() { this.start(); }

  private start() {
    this.worker = new Worker(new URL('./worker.ts', import.meta.url), { type: 'module' });
    this.worker.onmessage = (ev) => {
      const m = ev.data as { id: number; kind: string; value?: any; message?: string; done?: number; total?: number };
      const p = this.pending.get(m.id);
      if (!p) return;
      if (m.kind === 'progress') { p.progress?.(m.done!, m.total!); return; }
      this.pending.delete(m.id);
      if (m.kind === 'result') p.resolve(m.value); else p.reject(new Error(m.message));
    };
  }

  /** Runs `cmd` with `args` in the worker; `progress` hears (done, total). */
  call<T = string>(cmd: string, args: unknown[], progress?: Progress): Promise<T> {
    const id = this.next++;
    return new Promise<T>((resolve, reject) => {
      this.pending.set(id, { resolve, reject, progress });
      this.worker.postMessage({ id, cmd, args });
    });
  }

  /** Stops whatever runs: every pending call rejects with `Cancelled`. */
  cancel() {
    this.worker.terminate();
    for (const p of this.pending.values()) p.reject(new Cancelled());
    this.pending.clear();
    this.start();
  }

  get busy() { return this.pending.size > 0; }
}
