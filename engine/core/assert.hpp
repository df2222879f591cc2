// Precondition checks, on in debug builds and wherever WIREDEM_ASSERTIONS is
// defined (the sanitizer builds of scripts/build.sh); in release builds
// WIREDEM_ASSERT compiles to nothing. Use it for programming errors only,
// never for user input (that is validated once, in api/).
#pragma once

#include <cstdio>
#include <cstdlib>

#if !defined(NDEBUG) || defined(WIREDEM_ASSERTIONS)
#define WIREDEM_ASSERT(cond, msg)                                                          \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            std::fprintf(stderr, "%s:%d: assertion failed: %s (%s)\n", __FILE__, __LINE__, \
                #cond, msg);                                                               \
            std::abort();                                                                  \
        }                                                                                  \
    } while (false)
#else
#define WIREDEM_ASSERT(cond, msg) ((void)0)
#endif
