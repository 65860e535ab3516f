// DragThrottle: what follows a dragged point at most every `ms` while the map is dragged, and at
// once at rest. Within a drag the latest point of a throttled stretch is sent when the interval
// has passed (a trailing call), so the drag's last point is always sent. The panels (four
// requests, three chart redraws) and the real-time view's light table (729 KB, about 30 ms of the
// server's time at n = 1000) use it: per pointer event they took the cores the preview needs.

export class DragThrottle<T> {
  private last = -Infinity;
  private timer: ReturnType<typeof setTimeout> | undefined;

  constructor(
    private readonly ms: number,
    private readonly send: (input: T) => void,
    private readonly now: () => number = () => performance.now(),
  ) {}

  /** Sends `input` now unless `dragging` and the last send was under `ms` ago; then later. */
  request(input: T, dragging: boolean): void {
    clearTimeout(this.timer);
    this.timer = undefined;
    const elapsed = this.now() - this.last;
    if (!dragging || elapsed >= this.ms) {
      this.fire(input);
      return;
    }
    this.timer = setTimeout(() => {
      this.timer = undefined;
      this.fire(input);
    }, this.ms - elapsed);
  }

  private fire(input: T): void {
    this.last = this.now();
    this.send(input);
  }
}
