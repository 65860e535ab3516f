// A small typed store: the page's state as one object, changed only through update(), which
// calls every listener of a changed key once (so a change of environment and object together is
// one change, never the combination in between).

export class Store<S extends object> {
  private readonly listeners: { keys: readonly (keyof S)[]; fn: (state: S) => void }[] = [];

  constructor(readonly state: S) {}

  /** Sets the fields of `patch`, then calls each listener of any of them once. */
  update(patch: Partial<S>): void {
    const changed = Object.keys(patch) as (keyof S)[];
    Object.assign(this.state, patch);
    // Over a copy: a listener may remove itself (or another) while called.
    for (const l of [...this.listeners]) if (l.keys.some((k) => changed.includes(k))) l.fn(this.state);
  }

  /** Calls `fn` after every update that changes one of `keys`; returns what removes it. */
  on(keys: readonly (keyof S)[], fn: (state: S) => void): () => void {
    const listener = { keys, fn };
    this.listeners.push(listener);
    return () => {
      const at = this.listeners.indexOf(listener);
      if (at >= 0) this.listeners.splice(at, 1);
    };
  }
}
