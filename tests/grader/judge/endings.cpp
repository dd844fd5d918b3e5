#include "judge/endings.hpp"

#include "billiard/not_implemented.hpp"

#include <new>
#include <stdexcept>

namespace billiard::judge {

void write_current_exception(Writer& reply) {
  // Most derived first: NotImplemented is a logic_error, invalid_argument one too, and so on.
  try {
    throw;
  } catch (const NotImplemented& error) {
    reply << Ending::not_implemented << std::string(error.what()) << static_cast<std::int32_t>(error.task_number())
          << error.function() << error.file();
  } catch (const std::invalid_argument& error) {
    reply << Ending::invalid_argument << std::string(error.what());
  } catch (const std::domain_error& error) {
    reply << Ending::domain_error << std::string(error.what());
  } catch (const std::length_error& error) {
    reply << Ending::length_error << std::string(error.what());
  } catch (const std::out_of_range& error) {
    reply << Ending::out_of_range << std::string(error.what());
  } catch (const std::logic_error& error) {
    reply << Ending::logic_error << std::string(error.what());
  } catch (const std::range_error& error) {
    reply << Ending::range_error << std::string(error.what());
  } catch (const std::overflow_error& error) {
    reply << Ending::overflow_error << std::string(error.what());
  } catch (const std::underflow_error& error) {
    reply << Ending::underflow_error << std::string(error.what());
  } catch (const std::runtime_error& error) {  // with std::system_error, filesystem_error, ios_base::failure
    reply << Ending::runtime_error << std::string(error.what());
  } catch (const std::bad_alloc& error) {
    reply << Ending::bad_alloc << std::string(error.what());
  } catch (const std::exception& error) {
    reply << Ending::other_exception << std::string(error.what());
  } catch (...) {
    reply << Ending::not_an_exception << std::string("an exception that is not a std::exception");
  }
}

void throw_again(Ending ending, Reader& reply) {
  const auto message = reply.get<std::string>();
  switch (ending) {
    case Ending::not_implemented: {
      const auto task = reply.get<std::int32_t>();
      const auto function = reply.get<std::string>();
      const auto file = reply.get<std::string>();
      throw NotImplemented(task, function, file);
    }
    case Ending::invalid_argument: throw std::invalid_argument(message);
    case Ending::domain_error: throw std::domain_error(message);
    case Ending::length_error: throw std::length_error(message);
    case Ending::out_of_range: throw std::out_of_range(message);
    case Ending::logic_error: throw std::logic_error(message);
    case Ending::range_error: throw std::range_error(message);
    case Ending::overflow_error: throw std::overflow_error(message);
    case Ending::underflow_error: throw std::underflow_error(message);
    case Ending::runtime_error: throw std::runtime_error(message);
    case Ending::bad_alloc: throw std::bad_alloc();
    case Ending::other_exception: throw OtherException(message);
    case Ending::not_an_exception: throw NotAStandardException{message};
    case Ending::returned: break;
  }
  throw ProtocolError("a call that returned cannot be thrown again");
}

}  // namespace billiard::judge
