// Placeholder: the [photometry] tests are being written; this fails until they are.
#include <catch2/catch.hpp>

TEST_CASE("[photometry] tests are written", "[photometry]") {
    FAIL("the [photometry] tests are not written yet");
}
