function value = getfrsbf(filename, name, steps)
%GETFRSBF  One record of a SPACAR binary result file (.sbd, .sbm, .ltv).
%   V = GETFRSBF(FILE, NAME) returns record NAME of FILE, written by SPACAR or
%   by flexmbd. NAME is matched on its first four characters, in any case
%   ('nddof' is NDDO). A table (stored once) comes back as stored, rows x cols.
%   A record stored per step comes back for every step: with one step as that
%   step's rows x cols; with several as one row per step, each the step's
%   rows x cols values in MATLAB's column order (RESHAPE(V(k,:), rows, []) gives
%   step k's matrix). GETFRSBF(FILE, 'TDEF') is the number of steps.
%
%   V = GETFRSBF(FILE, NAME, STEPS) returns the steps STEPS (1-based) only, in
%   the same forms.
%
%   A record the file does not hold is the error 'ID not found' (identifier
%   getfrsbf:IDNotFound), as SPACAR's own tools expect. A file that ends inside
%   its steps gives its whole steps.
%
%   This reader is flexmbd's (matlab/ folder of its repository); the layout it
%   reads is described on flexmbd's page "SPACAR files".

  if nargin < 2
    error('getfrsbf:Arguments', 'use getfrsbf(FILE, NAME) or getfrsbf(FILE, NAME, STEPS)');
  end
  fid = fopen(filename, 'r', 'ieee-le');
  if fid < 0
    error('getfrsbf:FileNotFound', 'cannot open the SPACAR file %s', filename);
  end
  closer = onCleanup(@() fclose(fid));
  key = upper(char(name));
  key = [key(1:min(4, numel(key))), blanks(4 - min(4, numel(key)))];

  head = read_head(fid, filename);          % the file's identification
  if isempty(head) || head.type ~= 3
    error('getfrsbf:NotSpacar', '%s is not a SPACAR binary file', filename);
  end
  fseek(fid, head.rows * head.cols, 'cof');
  while true
    head = read_head(fid, filename);
    if isempty(head)
      break
    end
    if head.type == 0                         % TDEF: the per-step records follow
      if ~strcmp(head.name, 'TDEF')
        error('getfrsbf:Damaged', '%s: marker %s where TDEF was expected', filename, head.name);
      end
      if nargin > 2
        wanted = steps;
      else
        wanted = [];
      end
      value = step_record(fid, filename, key, head.rows, nargin > 2, wanted);
      return
    end
    width = head.size * head.rows * head.cols;
    if strcmp(head.name, key)
      value = read_values(fid, head, filename);
      value = reshape(value, head.cols, head.rows).';
      return
    end
    fseek(fid, width, 'cof');
  end
  error('getfrsbf:IDNotFound', 'ID not found');
end


function value = step_record(fid, filename, key, nsteps, chosen, steps)
  if strcmp(key, 'TDEF')
    value = nsteps;
    return
  end
  heads = {};
  while true
    head = read_head(fid, filename);
    if isempty(head)
      error('getfrsbf:Damaged', '%s ends inside the heads of its steps', filename);
    end
    if head.type == 0
      break                                   % TDAT: the values follow
    end
    heads{end + 1} = head; %#ok<AGROW>
  end
  sizes = cellfun(@(h) h.rows * h.cols, heads);
  at = find(cellfun(@(h) strcmp(h.name, key), heads), 1);
  if isempty(at)
    error('getfrsbf:IDNotFound', 'ID not found');
  end
  per_step = sum(sizes);
  start = ftell(fid);
  fseek(fid, 0, 'eof');
  whole = floor((ftell(fid) - start) / (8 * per_step));
  nsteps = min(nsteps, whole);               % a file cut inside its steps
  if ~chosen
    steps = 1:nsteps;
  end
  if any(steps < 1 | steps > nsteps | steps ~= round(steps))
    error('getfrsbf:Step', '%s holds steps 1 .. %d', filename, nsteps);
  end
  rows = heads{at}.rows;
  cols = heads{at}.cols;
  offset = sum(sizes(1:at - 1));
  value = zeros(numel(steps), rows * cols);
  for k = 1:numel(steps)
    fseek(fid, start + 8 * (per_step * (steps(k) - 1) + offset), 'bof');
    stored = fread(fid, rows * cols, 'float64');
    value(k, :) = reshape(reshape(stored, cols, rows).', 1, []);
  end
  if numel(steps) == 1
    value = reshape(value, rows, cols);
  end
end


function head = read_head(fid, filename)
  raw = fread(fid, 4, '*char').';
  if numel(raw) < 4
    head = [];
    return
  end
  numbers = fread(fid, 4, 'int32');
  if numel(numbers) < 4
    error('getfrsbf:Damaged', '%s ends inside a record head', filename);
  end
  head = struct('name', upper(raw), 'type', numbers(1), 'size', numbers(2), ...
                'rows', numbers(3), 'cols', numbers(4));
end


function values = read_values(fid, head, filename)
  count = head.rows * head.cols;
  switch head.type
    case 1
      values = fread(fid, count, 'int32');
    case 2
      values = fread(fid, count, 'float64');
    otherwise
      values = fread(fid, count, '*char');
  end
  if numel(values) < count
    error('getfrsbf:Damaged', '%s ends inside record %s', filename, head.name);
  end
  values = double(values);
end

