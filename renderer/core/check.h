// CHECK macros for programming errors (never for bad input): on failure they print the expression,
// its operands and the location, then abort. Bad input is reported with caustic::InputError.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <sstream>

#define CAUSTIC_CHECK(cond)                                                               \
    do {                                                                                  \
        if (!(cond)) {                                                                    \
            std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
            std::abort();                                                                 \
        }                                                                                 \
    } while (false)

#define CAUSTIC_CHECK_OP(a, op, b)                                                          \
    do {                                                                                    \
        if (!((a)op(b))) {                                                                  \
            std::ostringstream caustic_check_os;                                            \
            caustic_check_os << #a " " #op " " #b " with " #a " = " << (a) << ", " #b " = " \
                             << (b);                                                        \
            std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__,           \
                         caustic_check_os.str().c_str());                                   \
            std::abort();                                                                   \
        }                                                                                   \
    } while (false)

#define CAUSTIC_CHECK_EQ(a, b) CAUSTIC_CHECK_OP(a, ==, b)
#define CAUSTIC_CHECK_LT(a, b) CAUSTIC_CHECK_OP(a, <, b)
#define CAUSTIC_CHECK_LE(a, b) CAUSTIC_CHECK_OP(a, <=, b)
#define CAUSTIC_CHECK_GE(a, b) CAUSTIC_CHECK_OP(a, >=, b)
