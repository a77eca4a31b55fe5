## crslab: a serial port object that behaves like MATLAB's serial / serialport for the calls the
## course's scripts make, on top of instrument-control's serialport (see crs_octave_compat).

classdef crs_serial_compat < handle
  properties
    Port = "";
    BaudRate = 9600;
    Timeout = 10;            # seconds, as MATLAB's default
    InputBufferSize = 512;   # accepted and ignored (Octave's buffers grow)
    OutputBufferSize = 512;
    Status = "closed";
  endproperties
  properties (Access = private)
    dev = [];
  endproperties

  methods
    function obj = crs_serial_compat (port, baud, varargin)
      global CRS_SERIALPORT
      if (isempty (CRS_SERIALPORT))
        error ("crslab:compat", "call crs_octave_compat () first");
      endif
      obj.Port = port;
      obj.BaudRate = baud;
      obj.dev = CRS_SERIALPORT (port, "BaudRate", baud, "Timeout", obj.Timeout);
      obj.Status = "open";
      set (obj, varargin{:});
    endfunction

    function set (obj, varargin)
      for k = 1:2:numel (varargin)
        obj.(varargin{k}) = varargin{k + 1};
        if (strcmpi (varargin{k}, "BaudRate") && ! isempty (obj.dev))
          set (obj.dev, "BaudRate", varargin{k + 1});
        endif
      endfor
    endfunction

    function fopen (obj)
      obj.Status = "open";
    endfunction

    function count = fwrite (obj, data, precision)
      if (nargin < 3)
        precision = "uchar";
      endif
      count = fwrite (obj.dev, data, precision);
    endfunction

    function [data, count] = fread (obj, n, precision)
      ## MATLAB's fread: a double column; on a timeout, what arrived, with a warning
      if (nargin < 3)
        precision = "uchar";
      endif
      switch (lower (precision))
        case {"uchar", "uint8", "char", "schar", "int8"}
          width = 1; cls = "uint8";
        case {"int16", "uint16"}
          width = 2; cls = lower (precision);
        case {"int32", "uint32"}
          width = 4; cls = lower (precision);
        case {"float32", "single", "float"}
          width = 4; cls = "single";
        case {"float64", "double"}
          width = 8; cls = "double";
        otherwise
          error ("crslab:compat", "fread: precision %s is not supported", precision);
      endswitch
      set (obj.dev, "Timeout", obj.Timeout);
      raw = read (obj.dev, n * width, "uint8");
      whole = floor (numel (raw) / width);
      if (whole < n)
        warning ("crslab:timeout", ...
                 "The specified amount of data was not returned within the Timeout period.");
      endif
      data = double (typecast (uint8 (raw(1:whole * width)), cls))(:);
      if (strcmp (cls, "int8"))
        data = double (typecast (uint8 (raw(1:whole)), "int8"))(:);
      endif
      count = numel (data);
    endfunction

    function fclose (obj)
      obj.dev = [];   # the package's port closes when its last reference goes
      obj.Status = "closed";
    endfunction

    function delete (obj)
      obj.dev = [];
      obj.Status = "closed";
    endfunction
  endmethods
endclassdef
