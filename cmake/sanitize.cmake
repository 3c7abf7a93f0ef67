# Sanitizer and fuzzing builds. scripts/test.sh builds each in a folder of its own after the normal
# suite: CAUSTIC_SANITIZE for the C++ unit tests (CTest label "sanitize"), CAUSTIC_FUZZ for the
# libFuzzer targets in tests/fuzz (label "fuzz").
option(CAUSTIC_SANITIZE
       "Build with AddressSanitizer and UndefinedBehaviorSanitizer; any report ends the process" OFF)
option(CAUSTIC_FUZZ "Build the libFuzzer targets of tests/fuzz (clang only; implies the sanitizers)"
       OFF)

if(CAUSTIC_SANITIZE OR CAUSTIC_FUZZ)
    # -fno-sanitize-recover=all: undefined behaviour aborts like an ASan report, so a test fails
    # instead of printing a line nobody reads. GCC leaves float-cast-overflow out of "undefined"
    # (clang has it in): a NaN or out-of-range float converted to an integer is UB all the same.
    # Line tables (-g1) put file and line in the reports' stacks at little cost in build time.
    # _GLIBCXX_ASSERTIONS checks indices into standard containers (an index past the size but
    # within the capacity, or &v[0] of an empty vector, is no ASan report) without changing the ABI.
    add_compile_options(-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all
                        -fno-omit-frame-pointer -g1 -D_GLIBCXX_ASSERTIONS)
    add_link_options(-fsanitize=address,undefined,float-cast-overflow)
    # GCC 12's -Wmaybe-uninitialized misfires on std::regex's std::function under ASan's
    # instrumentation (tests/server/job_service_test.cpp); the normal build keeps the warning.
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
        add_compile_options(-Wno-maybe-uninitialized)
    endif()
endif()

if(CAUSTIC_FUZZ)
    # The C of third_party/ gets the same flags: the C compiler must be clang too.
    if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang" OR NOT CMAKE_C_COMPILER_ID STREQUAL "Clang")
        message(FATAL_ERROR "CAUSTIC_FUZZ needs clang (libFuzzer): configure with "
                            "-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++")
    endif()
    # Coverage feedback for the libraries; only the fuzz targets link libFuzzer's main.
    add_compile_options(-fsanitize=fuzzer-no-link)
endif()
