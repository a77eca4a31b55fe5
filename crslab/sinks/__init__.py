"""Where a run's output goes: every sink takes the board's serial bytes (with their tick) and the
scope rows, one chunk of ticks at a time, through one interface (:class:`crslab.sinks.sink.Sink`);
a :class:`crslab.sinks.sink.FanOut` hands each chunk to many."""
