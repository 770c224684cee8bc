// error.h: the error every library throws for bad user input.
#pragma once

#include <stdexcept>

namespace retroprism {

// A user input error; the message names the source (file, line, option), the field and what
// was expected, so that the command line can print it as it is.
class InputError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

} // namespace retroprism
