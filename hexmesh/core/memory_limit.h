// The memory a job may ask for: what large allocations are checked against before they happen.
#pragma once

namespace hexmesh {

// Bytes: the limit set by set_memory_limit, else half of this machine's physical memory.
double memory_limit();

// Sets the limit (bytes, > 0); 0 goes back to half of the machine's memory.
void set_memory_limit(double bytes);

// Bytes: the most memory this process has held so far (its peak resident set).
double peak_memory();

}  // namespace hexmesh
