# Read by CTest after the discovered GoogleTest tests (tests/CMakeLists.txt): each peer suite
# runs hundreds of scripts in one test. With Mesa's shader cache empty (a fresh machine, as CI
# is), VK-GL-CTS's sample took 282-286 s on this 2-core machine when each script had a child of
# its own, too close to the 300 s every other test gets; a single file of it takes lavapipe
# 80-90 s to compile. A COST starts them first in a fresh build folder, which has no timings yet
# for CTest to order by: started late, VK-GL-CTS's ran on alone after every other test.
foreach(suite vkglcts piglit vkrunner)
  set_tests_properties("Suites/PeerCases.PassAtTheirFloorsAndSkipWithReasons/${suite}" PROPERTIES TIMEOUT 900 COST 1000)
endforeach()
set_tests_properties("PiglitOracle.VerdictsAgreeWithPiglitsOwnAtTheMeasuredFloors" PROPERTIES TIMEOUT 900 COST 1000)
