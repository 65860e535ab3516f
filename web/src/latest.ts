// LatestOnly: runs an async task for the most recent input only, with at most one task in flight.
// While a task runs, newer inputs replace each other; when it finishes, the newest one (if any)
// starts. A dragging pointer thus never queues stale requests, and the image always catches up
// with the pointer's latest position. A request that supersedes (a new scene) also aborts the
// task in flight: its result, if it still comes, is dropped. `idle` (optional) is called when
// the latest input has been handled and nothing is left to run (for a loading indicator).

export class LatestOnly<T, R> {
  private running: AbortController | null = null;
  private pending: { input: T; startedAt: number } | null = null;

  constructor(
    private readonly task: (input: T, signal: AbortSignal) => Promise<R>,
    private readonly done: (result: R, input: T, startedAt: number) => void,
    private readonly failed: (error: unknown) => void = (e) => console.error(e),
    private readonly idle: () => void = () => {},
  ) {}

  /**
   * Asks for `input`; `startedAt` (performance.now() of the triggering event) is passed to done.
   * `supersede`: abort the task in flight instead of letting it finish.
   */
  request(input: T, startedAt: number = performance.now(), supersede = false): void {
    this.pending = { input, startedAt };
    if (supersede) this.running?.abort(new DOMException("superseded", "AbortError"));
    if (!this.running) void this.pump();
  }

  get busy(): boolean {
    return this.running !== null || this.pending !== null;
  }

  private async pump(): Promise<void> {
    while (this.pending) {
      const { input, startedAt } = this.pending;
      this.pending = null;
      const controller = (this.running = new AbortController());
      try {
        const result = await this.task(input, controller.signal);
        if (!controller.signal.aborted) this.done(result, input, startedAt);
      } catch (e) {
        if (!controller.signal.aborted) this.failed(e);
      }
    }
    this.running = null;
    this.idle();
  }
}
