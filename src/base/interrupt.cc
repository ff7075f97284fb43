// Ctrl-C and SIGTERM during a run (interrupt.h).
#include <base/interrupt.h>

#include <csignal>

namespace flextrack::base
{
namespace
{
volatile std::sig_atomic_t received = 0;

extern "C" void note_signal(const int signal)
{
  if (received != 0) // the second one: the default action (the process ends)
    {
      std::signal(signal, SIG_DFL);
      std::raise(signal);
      return;
    }
  received = signal;
}
} // namespace

void watch_interrupts()
{
  received = 0;
  struct sigaction action = {};
  action.sa_handler = note_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART; // a write or read under way goes on
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

void stop_watching_interrupts()
{
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

int interrupted() { return received; }

std::string signal_name(const int signal)
{
  return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "signal " + std::to_string(signal);
}
} // namespace flextrack::base
