
window.icrkitReport = { errors: [], ready: false, viewer: 'pending' };
(function () {
  var report = window.icrkitReport;
  report.update = function () {
    var element = document.getElementById('report-status');
    if (element) element.textContent = JSON.stringify(report);
  };
  window.onerror = function (message, source, line) {
    report.errors.push(String(message) + (line ? ' (line ' + line + ')' : ''));
    report.update();
  };
  window.addEventListener('unhandledrejection', function (event) {
    var reason = event.reason;
    report.errors.push('unhandled rejection: ' + (reason && reason.message ? reason.message : String(reason)));
    report.update();
  });
  // The page's Content-Security-Policy forbids every fetch: a violation
  // means something tried to leave the page.
  document.addEventListener('securitypolicyviolation', function (event) {
    report.errors.push('blocked by the page\'s CSP: ' + event.violatedDirective + ' ' + event.blockedURI);
    report.update();
  });
  var consoleError = console.error.bind(console);
  console.error = function () {
    report.errors.push(Array.prototype.map.call(arguments, String).join(' '));
    report.update();
    consoleError.apply(null, arguments);
  };
})();
