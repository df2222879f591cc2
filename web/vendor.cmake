# cmake -DNODE_MODULES=… -DOUT=… -P vendor.cmake
# Copies the files of the npm packages the page imports into OUT, with their
# licences (and uPlot.iife.min.js, the build `wiredem report` inlines). The
# page loads ES modules by relative path (an import map would be an inline
# script, which the Content-Security-Policy forbids), so three.js's OrbitControls, which imports the bare name 'three', is pointed at the copy
# beside it.
file(MAKE_DIRECTORY ${OUT})
file(COPY ${NODE_MODULES}/uplot/dist/uPlot.esm.js ${NODE_MODULES}/uplot/dist/uPlot.iife.min.js ${NODE_MODULES}/uplot/dist/uPlot.min.css
  ${NODE_MODULES}/three/build/three.module.js DESTINATION ${OUT})
file(COPY_FILE ${NODE_MODULES}/uplot/LICENSE ${OUT}/uPlot.LICENSE.txt)
file(COPY_FILE ${NODE_MODULES}/three/LICENSE ${OUT}/three.LICENSE.txt)
file(READ ${NODE_MODULES}/three/examples/jsm/controls/OrbitControls.js controls)
string(REPLACE "from 'three';" "from './three.module.js';" controls "${controls}")
if(NOT controls MATCHES "from './three.module.js';")
  message(FATAL_ERROR "OrbitControls.js no longer imports 'three' as expected: check web/vendor.cmake")
endif()
file(WRITE ${OUT}/OrbitControls.js "${controls}")
