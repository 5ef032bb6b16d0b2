// Fault identifiers (as they arrive in sender_fault / receiver_fault) → display strings (SPEC §6).
window.OCP_FAULT_DISPLAY = Object.freeze({
  VehicleNoResponse: "Vehicle No Response",
  NoControlMessage: "No Control Message",
  CameraLost: "Camera Lost",
  StreamerSlow: "Streamer Slow",
  HighLatency: "High Latency",
  OperatorStationHasError: "Operator Station Has Error",
  InvalidMac: "Latency Loop Not Closed",
  ControlThreadChannelSlow: "Control Thread Channel Slow",
  InputLost: "Input Lost",
  NoFeedbackMessage: "No Feedback Message",
  VehicleControlInactive: "Vehicle Control Inactive",
});
