#include <app/exit_status.h>
#include <base/input_error.h>
#include <base/interrupt.h>
#include <base/solver_error.h>

#include <deal.II/base/exceptions.h>

#include <sstream>

namespace flextrack::app
{
CommandOutcome run_guarded(const std::function<int()> &command)
{
  try
    {
      return {command(), ""};
    }
  catch (const InputError &e)
    {
      return {2, std::string("error: ") + e.what()};
    }
  catch (const base::Interrupted &e) // before SolverError, which it is
    {
      return {128 + e.signal(), e.what()};
    }
  catch (const SolverError &e)
    {
      return {3, std::string("solver failure: ") + e.what()};
    }
  catch (const dealii::ExceptionBase &e)
    {
      std::ostringstream info;
      e.print_info(info);
      return {4, "internal error:" + info.str()};
    }
  catch (const std::exception &e)
    {
      return {4, std::string("internal error: ") + e.what()};
    }
}
namespace
{
bool collective = false;
} // namespace

void start_collective_work() { collective = true; }
bool collective_work_started() { return collective; }
} // namespace flextrack::app
