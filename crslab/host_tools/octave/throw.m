## crslab: throw (E) for the MException stand-in: raises its identifier and message.
function throw (e)
  error (struct ("identifier", e.identifier, "message", e.message));
endfunction
