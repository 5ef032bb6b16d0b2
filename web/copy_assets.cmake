# Copies the web view's static files into the build tree (cmake -DSOURCE=web -DDESTINATION=build/web -P …).
# Only what a browser loads: the SDK shim, the pages and the chart library uPlot, vendored in
# web/vendor (MIT, its licence beside it; no npm needed) — never node_modules or the tests.
# file(COPY) skips files that did not change.
file(MAKE_DIRECTORY ${DESTINATION})
file(COPY ${SOURCE}/index.html ${SOURCE}/favicon.svg ${SOURCE}/sdk ${SOURCE}/dashboard ${SOURCE}/minimal DESTINATION ${DESTINATION})
file(COPY ${SOURCE}/vendor/uPlot.iife.min.js ${SOURCE}/vendor/uPlot.min.css ${SOURCE}/vendor/uPlot.LICENSE
     DESTINATION ${DESTINATION}/vendor)
