# Read by CTest after the discovered GoogleTest tests (tests/CMakeLists.txt): each peer suite
# runs hundreds of scripts in one test, one after the other. VK-GL-CTS's sample took 282-286 s on
# this 2-core machine with Mesa's shader cache empty (a fresh machine, as CI is), too close to the
# 300 s every other test gets.
foreach(suite vkglcts piglit vkrunner)
  set_tests_properties("Suites/PeerCases.PassAtTheirFloorsAndSkipWithReasons/${suite}" PROPERTIES TIMEOUT 900)
endforeach()
