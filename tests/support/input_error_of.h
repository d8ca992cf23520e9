// Catching the InputError a call throws, for tests of code that reports bad input.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "model/core/error.h"

namespace orcs::test_support {

/// The what() of the InputError `call` throws; fails the test when it throws nothing or something else.
template <typename Call>
std::string InputErrorOf(Call call) {
  try {
    call();
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

}  // namespace orcs::test_support
