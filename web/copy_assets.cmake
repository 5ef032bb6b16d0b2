# Copies the web view's static files into the build tree (cmake -DSOURCE=web -DDESTINATION=build/web -P …).
# Only what a browser loads: the SDK shim, the pages and the vendored chart library — never
# node_modules or the tests. file(COPY) skips files that did not change.
file(MAKE_DIRECTORY ${DESTINATION})
file(COPY ${SOURCE}/index.html ${SOURCE}/favicon.svg ${SOURCE}/sdk ${SOURCE}/dashboard ${SOURCE}/minimal DESTINATION ${DESTINATION})
set(UPLOT ${SOURCE}/node_modules/uplot/dist)
if(EXISTS ${UPLOT}/uPlot.iife.min.js)
  file(COPY ${UPLOT}/uPlot.iife.min.js ${UPLOT}/uPlot.min.css DESTINATION ${DESTINATION}/vendor)
else()
  message(WARNING "web/node_modules/uplot missing (run scripts/setup): the dashboard draws its charts without uPlot")
endif()
