// `untangle formats`: what can be read and what can be written.
#pragma once

namespace untangle::app {

// Prints the readable and the writable formats, one extension a line. Returns the exit code (0).
int run_formats();

}  // namespace untangle::app
