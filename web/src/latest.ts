// LatestOnly: runs an async task for the most recent input only, with at most one task in flight.
// While a task runs, newer inputs replace each other; when it finishes, the newest one (if any)
// starts. A dragging pointer thus never queues stale requests, and the image always catches up
// with the pointer's latest position.

export class LatestOnly<T, R> {
  private running = false;
  private pending: { input: T; startedAt: number } | null = null;

  constructor(
    private readonly task: (input: T) => Promise<R>,
    private readonly done: (result: R, input: T, startedAt: number) => void,
    private readonly failed: (error: unknown) => void = (e) => console.error(e),
  ) {}

  /** Asks for `input`; `startedAt` (performance.now() of the triggering event) is passed to done. */
  request(input: T, startedAt: number = performance.now()): void {
    this.pending = { input, startedAt };
    if (!this.running) void this.pump();
  }

  get busy(): boolean {
    return this.running || this.pending !== null;
  }

  private async pump(): Promise<void> {
    this.running = true;
    while (this.pending) {
      const { input, startedAt } = this.pending;
      this.pending = null;
      try {
        const result = await this.task(input);
        this.done(result, input, startedAt);
      } catch (e) {
        this.failed(e);
      }
    }
    this.running = false;
  }
}
