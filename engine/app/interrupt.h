// Ctrl-C and SIGTERM during a render: the handler only sets a flag that the wave loop polls.
#pragma once

namespace fh {

void install_interrupt_handlers();
bool interrupt_requested();

}  // namespace fh
