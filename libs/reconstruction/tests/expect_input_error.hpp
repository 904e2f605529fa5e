#pragma once
/// \file
/// The InputError a call throws, for tests that check what it names.

#include <icrkit/core/error.hpp>

#include <gtest/gtest.h>

namespace icrkit::reconstruction::testing_support {

/// Runs `f` and returns the InputError it threw; records a failure (and
/// returns an empty error) when it threw none.
template <typename Function>
InputError expectInputError(Function&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError thrown";
  return InputError("", "", "");
}

}  // namespace icrkit::reconstruction::testing_support
