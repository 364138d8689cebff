// Ctrl-C and SIGTERM during a render: the first only sets a flag that the wave loop polls; a second one
// while the first is pending exits at once (status 130, async-signal-safe).
#pragma once

namespace fh {

void install_interrupt_handlers();
bool interrupt_requested();

}  // namespace fh
